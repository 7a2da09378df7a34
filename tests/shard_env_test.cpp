// `batch --shard auto`: the shard K/N from a Slurm job array's or a Kubernetes indexed Job's
// variables, given as a map instead of the process environment.
#include "cli/shard_env.h"

#include <gtest/gtest.h>

#include <functional>
#include <map>

#include "renderer/core/errors.h"
#include "tests/support/environment_map.h"
#include "tests/support/input_error.h"

namespace omnishadow::cli::shard_env_test {
namespace {

using test_support::inputError;

using test_support::Variables;

Environment environment(const Variables& variables) {
  return test_support::environmentOf(variables);
}

std::string shardOf(const Variables& variables, std::optional<int> count = std::nullopt) {
  return shardFromEnvironment(environment(variables), count);
}

TEST(ShardEnvTest, SlurmArrayWithTaskCount) {
  // sbatch --array=0-3
  EXPECT_EQ(shardOf({{"SLURM_ARRAY_TASK_ID", "0"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}), "0/4");
  EXPECT_EQ(shardOf({{"SLURM_ARRAY_TASK_ID", "3"},
                     {"SLURM_ARRAY_TASK_COUNT", "4"},
                     {"SLURM_ARRAY_TASK_MIN", "0"},
                     {"SLURM_ARRAY_TASK_MAX", "3"}}),
            "3/4");
  // sbatch --array=1-8: K counts from the first task.
  EXPECT_EQ(shardOf({{"SLURM_ARRAY_TASK_ID", "1"},
                     {"SLURM_ARRAY_TASK_COUNT", "8"},
                     {"SLURM_ARRAY_TASK_MIN", "1"}}),
            "0/8");
}

TEST(ShardEnvTest, SlurmArrayWithMinAndMaxAndStep) {
  EXPECT_EQ(shardOf({{"SLURM_ARRAY_TASK_ID", "5"},
                     {"SLURM_ARRAY_TASK_MIN", "1"},
                     {"SLURM_ARRAY_TASK_MAX", "10"}}),
            "4/10");
  // sbatch --array=0-10:5 runs tasks 0, 5 and 10.
  EXPECT_EQ(shardOf({{"SLURM_ARRAY_TASK_ID", "10"},
                     {"SLURM_ARRAY_TASK_MIN", "0"},
                     {"SLURM_ARRAY_TASK_MAX", "10"},
                     {"SLURM_ARRAY_TASK_STEP", "5"}}),
            "2/3");
  // --shard-count overrides the array's size.
  EXPECT_EQ(shardOf({{"SLURM_ARRAY_TASK_ID", "2"}}, 3), "2/3");
}

TEST(ShardEnvTest, KubernetesIndexedJobNeedsShardCount) {
  EXPECT_EQ(shardOf({{"JOB_COMPLETION_INDEX", "0"}}, 5), "0/5");
  EXPECT_EQ(shardOf({{"JOB_COMPLETION_INDEX", "4"}}, 5), "4/5");
  EXPECT_EQ(inputError([] {
              shardOf({{"JOB_COMPLETION_INDEX", "2"}});
            }),
            "--shard auto: JOB_COMPLETION_INDEX is set; pass --shard-count N with the Job's "
            "completions");
  EXPECT_EQ(inputError([] {
              shardOf({{"JOB_COMPLETION_INDEX", "5"}}, 5);
            }),
            "--shard auto: JOB_COMPLETION_INDEX=5 is not below --shard-count 5");
}

TEST(ShardEnvTest, ClearErrorsWhenNothingOrTooMuchOrNonsenseIsSet) {
  EXPECT_EQ(inputError([] { shardOf({}); }),
            "--shard auto: no scheduler variable is set (SLURM_ARRAY_TASK_ID for a Slurm job "
            "array, JOB_COMPLETION_INDEX for a Kubernetes indexed Job); pass --shard K/N");
  EXPECT_EQ(inputError([] {
              shardOf({{"SLURM_ARRAY_TASK_ID", "0"}, {"JOB_COMPLETION_INDEX", "0"}});
            }),
            "--shard auto: both SLURM_ARRAY_TASK_ID and JOB_COMPLETION_INDEX are set; pass --shard "
            "K/N");
  EXPECT_EQ(inputError([] {
              shardOf({{"SLURM_ARRAY_TASK_ID", "0"}});
            }),
            "--shard auto: SLURM_ARRAY_TASK_ID is set but not SLURM_ARRAY_TASK_COUNT, nor "
            "SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_MAX; pass --shard-count N");
  EXPECT_EQ(inputError([] {
              shardOf({{"SLURM_ARRAY_TASK_ID", "x1"}, {"SLURM_ARRAY_TASK_COUNT", "4"}});
            }),
            "--shard auto: SLURM_ARRAY_TASK_ID=x1: expected a whole number");
  EXPECT_EQ(inputError([] {
              shardOf({{"SLURM_ARRAY_TASK_ID", "4"}, {"SLURM_ARRAY_TASK_COUNT", "4"}});
            }),
            "--shard auto: SLURM_ARRAY_TASK_ID=4 is not one of 4 tasks from 0 in steps of 1");
  EXPECT_EQ(inputError([] {
              shardOf({{"SLURM_ARRAY_TASK_ID", "3"},
                       {"SLURM_ARRAY_TASK_MIN", "0"},
                       {"SLURM_ARRAY_TASK_MAX", "10"},
                       {"SLURM_ARRAY_TASK_STEP", "5"}});
            }),
            "--shard auto: SLURM_ARRAY_TASK_ID=3 is not one of 3 tasks from 0 in steps of 5");
}

TEST(ShardEnvTest, ResolveLeavesExplicitShardsAlone) {
  const Environment slurm =
      environment({{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "2"}});
  EXPECT_EQ(resolveShard("", 0, slurm), "");
  EXPECT_EQ(resolveShard("0/3", 0, slurm), "0/3");
  EXPECT_EQ(resolveShard("auto", 0, slurm), "1/2");
  EXPECT_EQ(inputError([&] { resolveShard("0/3", 3, slurm); }),
            "--shard-count: only used with --shard auto");
}

}  // namespace
}  // namespace omnishadow::cli::shard_env_test
