#include "cli/shard_env.h"

#include <charconv>
#include <cstdlib>

#include "renderer/core/errors.h"

namespace omnishadow::cli {
namespace {

// A variable's value as a whole number; nullopt when it is not set. Throws InputError for any
// other text.
std::optional<long> integer(const Environment& environment, const std::string& name) {
  const std::optional<std::string> value = environment(name);
  if (!value) return std::nullopt;
  long number = 0;
  const auto [end, error] = std::from_chars(value->data(), value->data() + value->size(), number);
  if (value->empty() || error != std::errc() || end != value->data() + value->size())
    throw InputError("--shard auto: " + name + "=" + *value + ": expected a whole number");
  return number;
}

std::string shard(long index, long count) {
  return std::to_string(index) + "/" + std::to_string(count);
}

std::string slurmShard(const Environment& environment, std::optional<int> shardCount) {
  const long id = *integer(environment, "SLURM_ARRAY_TASK_ID");
  const std::optional<long> taskCount = integer(environment, "SLURM_ARRAY_TASK_COUNT");
  const std::optional<long> min = integer(environment, "SLURM_ARRAY_TASK_MIN");
  const std::optional<long> max = integer(environment, "SLURM_ARRAY_TASK_MAX");
  const long step = integer(environment, "SLURM_ARRAY_TASK_STEP").value_or(1);
  if (step < 1)
    throw InputError("--shard auto: SLURM_ARRAY_TASK_STEP=" + std::to_string(step) +
                     ": expected 1 or more");
  const long first = min.value_or(0);
  std::optional<long> count = taskCount;
  if (!count && min && max) count = (*max - *min) / step + 1;
  if (shardCount) count = *shardCount;
  if (!count)
    throw InputError(
        "--shard auto: SLURM_ARRAY_TASK_ID is set but not SLURM_ARRAY_TASK_COUNT, nor "
        "SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_MAX; pass --shard-count N");
  const long index = (id - first) / step;
  if (id < first || (id - first) % step != 0 || index >= *count)
    throw InputError("--shard auto: SLURM_ARRAY_TASK_ID=" + std::to_string(id) + " is not one of " +
                     std::to_string(*count) + " tasks from " + std::to_string(first) +
                     " in steps of " + std::to_string(step));
  return shard(index, *count);
}

}  // namespace

Environment processEnvironment() {
  return [](const std::string& name) -> std::optional<std::string> {
    const char* value = std::getenv(name.c_str());
    return value ? std::optional<std::string>(value) : std::nullopt;
  };
}

std::string shardFromEnvironment(const Environment& environment, std::optional<int> shardCount) {
  const bool slurm = environment("SLURM_ARRAY_TASK_ID").has_value();
  const bool kubernetes = environment("JOB_COMPLETION_INDEX").has_value();
  if (slurm && kubernetes)
    throw InputError(
        "--shard auto: both SLURM_ARRAY_TASK_ID and JOB_COMPLETION_INDEX are set; pass --shard "
        "K/N");
  if (slurm) return slurmShard(environment, shardCount);
  if (!kubernetes)
    throw InputError(
        "--shard auto: no scheduler variable is set (SLURM_ARRAY_TASK_ID for a Slurm job "
        "array, JOB_COMPLETION_INDEX for a Kubernetes indexed Job); pass --shard K/N");
  const long index = *integer(environment, "JOB_COMPLETION_INDEX");
  if (!shardCount)
    throw InputError(
        "--shard auto: JOB_COMPLETION_INDEX is set; pass --shard-count N with the Job's "
        "completions");
  if (index < 0 || index >= *shardCount)
    throw InputError("--shard auto: JOB_COMPLETION_INDEX=" + std::to_string(index) +
                     " is not below --shard-count " + std::to_string(*shardCount));
  return shard(index, *shardCount);
}

std::string resolveShard(const std::string& shard, int shardCount, const Environment& environment) {
  if (shard != "auto") {
    if (shardCount > 0) throw InputError("--shard-count: only used with --shard auto");
    return shard;
  }
  return shardFromEnvironment(environment,
                              shardCount > 0 ? std::optional<int>(shardCount) : std::nullopt);
}

}  // namespace omnishadow::cli
