#include "cli/steady_frames.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "renderer/core/errors.h"

namespace omnishadow::cli {
namespace {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

void printSteadyFrames(Renderer& renderer, const RenderJob& job, const LoadedJob& loaded,
                       int repeat) {
  LoadedJob moved = loaded;
  for (Light& light : moved.lights) light.position.x += 0.001f;
  std::map<std::string, std::vector<double>> stages;
  std::vector<std::string> order;
  std::vector<double> frames;
  for (int i = 0; i < repeat; ++i) {
    StageTimes times;
    const Frame frame = renderJob(renderer, job, i % 2 == 0 ? moved : loaded, times);
    if (frame.shadowMapsReused != 0)
      throw RenderError("--repeat: a shadow map was reused, so the frame time would be too low");
    double sum = 0.0;
    for (const auto& [stage, ms] : times.stages()) {
      if (!stages.count(stage)) order.push_back(stage);
      stages[stage].push_back(ms);
      // Everything the frame draws and reads back (not the shaders and uploads, which the first
      // frame paid for): a frame with AOV layers or masks pays for its layer passes too.
      if (stage == "shadow maps" || stage == "lighting" || stage == "readback" ||
          stage == "layers" || stage == "light views")
        sum += ms;
    }
    frames.push_back(sum);
    for (const auto& [stage, ms] : times.waits()) {
      const std::string wait = kGpuWaitPrefix + stage;
      if (!stages.count(wait)) order.push_back(wait);
      stages[wait].push_back(ms);
    }
  }
  std::fprintf(stderr, "steady frames %d\n", repeat);
  for (const std::string& stage : order)
    std::fprintf(stderr, "steady %-12s %8.1f\n", stage.c_str(), median(stages[stage]));
  std::fprintf(stderr, "steady frame %8.1f\n", median(frames));
}

}  // namespace omnishadow::cli
