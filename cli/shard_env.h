#pragma once

#include <functional>
#include <optional>
#include <string>

namespace omnishadow::cli {

// Looks an environment variable up: std::getenv in the product, a map in tests.
using Environment = std::function<std::optional<std::string>(const std::string& name)>;
Environment processEnvironment();

// The "K/N" that `batch --shard auto` means, from the scheduler's variables:
//   Slurm job array  SLURM_ARRAY_TASK_ID, with SLURM_ARRAY_TASK_COUNT or _MIN and _MAX (and
//                    _STEP, when the array has one); K counts from the array's first task.
//                    `shardCount`, when given, overrides the array's size.
//   Kubernetes       JOB_COMPLETION_INDEX (an indexed Job) with `shardCount` (--shard-count N,
//                    the Job's completions), which the Job does not put in the environment.
// Throws InputError naming the variables when none is set, both are, or they do not add up.
std::string shardFromEnvironment(const Environment& environment, std::optional<int> shardCount);

// `--shard` as given, with "auto" resolved by shardFromEnvironment(); "" stays "" (no shard).
// --shard-count without --shard auto is a usage error.
std::string resolveShard(const std::string& shard, int shardCount, const Environment& environment);

}  // namespace omnishadow::cli
