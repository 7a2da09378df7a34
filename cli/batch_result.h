#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "renderer/core/stage_timer.h"

namespace omnishadow::cli {

enum class JobStatus { Rendered, Skipped, Failed };

// What became of one batch job: in the report, in the log, and over the worker pipe.
struct JobResult {
  JobStatus status = JobStatus::Failed;
  std::string error;
  std::vector<std::filesystem::path> outputs;
  std::vector<std::string> warnings;
  StageTimes times;
  double milliseconds = 0.0;  // load + render + encode
};

}  // namespace omnishadow::cli
