#include "cli/frame_set.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <thread>

#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"
#include "renderer/render/renderer.h"
#include "renderer/view/camera_sets.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

double parseSeconds(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value))
    throw InputError(option + ": \"" + text + "\" is not a number of seconds");
  return value;
}

// N of "hemisphere:N", or InputError.
int hemisphereCount(const std::string& views) {
  const std::string prefix = "hemisphere:";
  int count = 0;
  if (views.rfind(prefix, 0) == 0) {
    try {
      std::size_t used = 0;
      count = std::stoi(views.substr(prefix.size()), &used);
      if (used != views.size() - prefix.size()) count = 0;
    } catch (const std::exception&) {
      count = 0;
    }
  }
  if (count < 1 || count > 100000)
    throw InputError("--views " + views + ": expected hemisphere:N with N in [1, 100000]");
  return count;
}

fs::path numbered(const fs::path& pattern, int number) {
  return pattern.empty() ? pattern : fs::path(numberedPath(pattern.string(), number));
}

// The job of one frame: outputs numbered, the frame's time.
RenderJob frameJob(const RenderJob& pattern, int number, std::optional<double> time) {
  RenderJob job = pattern;
  for (fs::path& path : job.png) path = numbered(path, number);
  for (fs::path& path : job.exr) path = numbered(path, number);
  job.aov = numbered(job.aov, number);
  job.dumpDepth = numbered(job.dumpDepth, number);
  job.lightViews = numbered(job.lightViews, number);
  job.time = time;
  return job;
}

void checkPatterns(const RenderJob& job) {
  const auto check = [](const std::string& option, const fs::path& path) {
    if (!path.empty() && path.filename().string().find('#') == std::string::npos)
      throw InputError(option + " " + path.string() +
                       ": a sequence or camera set writes one file per frame; put #### in the "
                       "file name for the frame number (e.g. frames/walk_####.png)");
  };
  for (const fs::path& path : job.png) check("-o", path);
  for (const fs::path& path : job.exr) check("-o", path);
  check("--aov", job.aov);
  check("--dump-depth", job.dumpDepth);
  check("--light-views", job.lightViews);
}

}  // namespace

void addFrameSetOptions(CLI::App& render, FrameSetOptions& o) {
  render.add_option("--time-range", o.timeRange,
                    "Render a sequence from START to END seconds (START:END) at --fps; outputs "
                    "are patterns such as frames/walk_####.png");
  render.add_option("--fps", o.fps, "Frames per second of --time-range (default 24)")
      ->check(CLI::PositiveNumber);
  render.add_option("--times", o.times, "Render a sequence at these times in seconds: t1,t2,...");
  render
      .add_option("--orbit", o.orbit,
                  "Render N views on a circle around the scene center, at the camera's "
                  "elevation and distance (numbered like a sequence)")
      ->check(CLI::Range(1, 100000));
  render.add_option("--views", o.views,
                    "Render a camera set: hemisphere:N spreads N views evenly over the upper "
                    "hemisphere, facing the scene center");
  render.add_flag("--camera-json", o.cameraJson,
                  "Write <image>.camera.json beside each image: size, intrinsics, OpenGL and "
                  "OpenCV camera matrices, projection, time, glTF camera");
}

bool isFrameSet(const FrameSetOptions& o) {
  return !o.timeRange.empty() || !o.times.empty() || o.orbit > 0 || !o.views.empty();
}

std::vector<double> sequenceTimes(const FrameSetOptions& o) {
  if (!o.timeRange.empty() && !o.times.empty())
    throw InputError("--time-range, --times: give one of them");
  std::vector<double> times;
  if (!o.times.empty()) {
    std::istringstream in(o.times);
    std::string item;
    while (std::getline(in, item, ',')) times.push_back(parseSeconds("--times", item));
    if (times.empty()) throw InputError("--times: expected t1,t2,... in seconds");
    return times;
  }
  const std::size_t colon = o.timeRange.find(':');
  if (colon == std::string::npos)
    throw InputError("--time-range " + o.timeRange + ": expected START:END in seconds");
  const double start = parseSeconds("--time-range", o.timeRange.substr(0, colon));
  const double end = parseSeconds("--time-range", o.timeRange.substr(colon + 1));
  if (end < start) throw InputError("--time-range " + o.timeRange + ": END is before START");
  // Frame k at start + k / fps; the small tolerance keeps an END that is a whole number of
  // frames (0:5 at 24 fps) despite rounding.
  const double frames = std::floor((end - start) * o.fps + 1e-6);
  if (frames >= 1e6) throw InputError("--time-range " + o.timeRange + ": over a million frames");
  for (int k = 0; k <= static_cast<int>(frames); ++k) times.push_back(start + k / o.fps);
  return times;
}

std::string numberedPath(const std::string& pattern, int number) {
  const std::size_t last = pattern.find_last_of('#');
  const std::size_t slash = pattern.find_last_of('/');
  if (last == std::string::npos || (slash != std::string::npos && last < slash)) return pattern;
  std::size_t first = last;
  while (first > 0 && pattern[first - 1] == '#') --first;
  std::string digits = std::to_string(number);
  const std::size_t width = last - first + 1;
  if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
  return pattern.substr(0, first) + digits + pattern.substr(last + 1);
}

int renderFrameSet(const RenderJob& job, const FrameSetOptions& o, const DeviceOptions& device,
                   std::vector<std::string>& warnings) {
  const bool sequence = !o.timeRange.empty() || !o.times.empty();
  const bool views = o.orbit > 0 || !o.views.empty();
  if (o.orbit > 0 && !o.views.empty()) throw InputError("--orbit, --views: give one of them");
  if (sequence && views)
    throw InputError(
        "--orbit/--views: a camera set is rendered at one time (--time), not with "
        "--time-range or --times");
  if (sequence && job.time)
    throw InputError("--time: a sequence takes its times from --time-range or --times");
  checkPatterns(job);
  const std::vector<double> times =
      sequence ? sequenceTimes(o) : std::vector<double>{job.time.value_or(0.0)};
  const int viewCount = o.orbit > 0 ? o.orbit : !o.views.empty() ? hemisphereCount(o.views) : 0;
  const int frames = sequence ? static_cast<int>(times.size()) : viewCount;
  const auto frameTime = [&](int k) -> std::optional<double> {
    if (sequence) return times[static_cast<std::size_t>(k)];
    return job.time;
  };
  // Every frame's outputs are checked before anything is rendered.
  for (int k = 0; k < frames; ++k) validateJob(frameJob(job, k, frameTime(k)));

  StageTimes stages;
  ScopedStage loadStage(stages, "load");
  RenderJob first = frameJob(job, 0, frameTime(0));
  LoadedJob loaded = loadJob(first);
  warnings = loaded.warnings;
  loadStage.stop();
  ScopedStage contextStage(stages, "context");
  const std::unique_ptr<Renderer> renderer = openRenderer(device);
  contextStage.stop();
  setEncoderThreads(static_cast<int>(std::thread::hardware_concurrency()));

  std::vector<CameraView> cameraSet;
  if (views) {
    const glm::vec3 center = loaded.scene().bounds.center();
    cameraSet = o.orbit > 0
                    ? orbitViews(loaded.camera.eye, center, o.orbit)
                    : hemisphereViews(center, glm::length(loaded.camera.eye - center), viewCount);
  }
  // Automatic framing follows the scene bounds; a sequence keeps the first frame's so that the
  // camera does not drift with the pose.
  const ViewCamera firstCamera = loaded.camera;
  double poseMs = 0.0;
  const auto started = std::chrono::steady_clock::now();
  for (int k = 0; k < frames; ++k) {
    RenderJob frame = frameJob(job, k, frameTime(k));
    if (views) {
      frame.camera.eye = cameraSet[static_cast<std::size_t>(k)].eye;
      frame.camera.target = cameraSet[static_cast<std::size_t>(k)].target;
    }
    if (k > 0 || views) {
      const auto t0 = std::chrono::steady_clock::now();
      ScopedStage poseStage(stages, "pose");
      const std::vector<std::string> more = poseJob(frame, frame.time, loaded);
      poseMs +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      for (const std::string& w : more)
        if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
      if (sequence && firstCamera.gltfCamera < 0) loaded.camera = firstCamera;
    }
    const Frame image = renderJob(*renderer, frame, loaded, stages);
    for (const std::string& w : image.warnings)
      if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
    ScopedStage encodeStage(stages, "encode");
    writeJobOutputs(frame, loaded, image);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  printWarnings(warnings);
  const RenderJob firstFrame = frameJob(job, 0, frameTime(0));
  const RenderJob lastFrame = frameJob(job, frames - 1, frameTime(frames - 1));
  const fs::path firstFile = firstFrame.outputFiles().front();
  const fs::path lastFile = lastFrame.outputFiles().front();
  std::printf("wrote %d frames (%dx%d): %s ... %s\n", frames, loaded.camera.width,
              loaded.camera.height, firstFile.c_str(), lastFile.c_str());
  if (device.stats) {
    printStats(stages);
    std::fprintf(stderr, "omnishadow: %d frames in %.3f s: %.2f frames/s, posing %.1f%%\n", frames,
                 seconds, frames / seconds, seconds > 0 ? poseMs / 10.0 / seconds : 0.0);
  }
  return 0;
}

}  // namespace omnishadow::cli
