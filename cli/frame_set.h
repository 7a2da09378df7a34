#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli/common_options.h"
#include "cli/render_job.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Several frames from one `render`: a sequence of times (--time-range with --fps, or --times)
// or a camera set (--orbit N, --views hemisphere:N), rendered in one process with one context
// and one loaded scene, each written to numbered files.
struct FrameSetOptions {
  std::string timeRange;  // "START:END" seconds
  double fps = 24.0;
  std::string times;  // "t1,t2,..."
  int orbit = 0;
  std::string views;  // "hemisphere:N"
  bool cameraJson = false;
};

// Adds --time-range, --fps, --times, --orbit, --views and --camera-json.
void addFrameSetOptions(CLI::App& render, FrameSetOptions& options);

// Whether the options ask for more than one frame.
bool isFrameSet(const FrameSetOptions& options);

// The times of a sequence: START, START + 1/fps, ... up to END (included when it falls on a
// frame); or the --times list. InputError for malformed or empty ranges.
std::vector<double> sequenceTimes(const FrameSetOptions& options);

// `pattern` with its last run of '#' replaced by `number`, zero-padded to the run's length;
// the same pattern without '#' is returned unchanged.
std::string numberedPath(const std::string& pattern, int number);

// Renders every frame of the set for `job` (whose outputs are patterns with '#'); returns the
// exit status. Warnings (the first frame's, then any new ones) go to `warnings`.
int renderFrameSet(const RenderJob& job, const FrameSetOptions& options,
                   const DeviceOptions& device, std::vector<std::string>& warnings);

}  // namespace omnishadow::cli
