#pragma once

#include <optional>
#include <string>

#include "cli/process_environment.h"

namespace omnishadow::cli {

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
