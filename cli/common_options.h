#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "renderer/core/stage_timer.h"

namespace CLI {
class App;
}

namespace omnishadow {
class Renderer;
}

namespace omnishadow::cli {

struct RenderJob;

// The scene inputs that `render`, `verify`, `batch` and `info` share, as given on the command
// line.
struct SceneInputOptions {
  std::string scene;  // empty = the built-in demo scene (render, verify)
  std::string lights;
  bool noGltfLights = false;
  bool allowExternalUris = false;
  double maxMemoryMiB = 4096.0;
  std::string shadowPass = "auto";
  std::string depthPrepass = "auto";
  std::string finishEachStage = "auto";
  int sceneIndex = -1;
  std::optional<double> time;   // --time SECONDS; nullopt = the rest pose
  std::string animation;        // --animation NAME|INDEX|all; empty = all
  std::string materialVariant;  // --variant NAME|INDEX; empty = the default materials
};

// Which command registers the scene inputs: each takes a different part of the group.
enum class SceneInputCommand { Render, Verify, Batch, Info };

// Adds the scene inputs `command` takes: the scene (a positional argument, but for batch),
// -l/--lights, --allow-external-uris and --scene; for render, verify and batch also
// --no-gltf-lights and --max-memory; for render and batch --shadow-pass.
void addSceneInputOptions(CLI::App& app, SceneInputOptions& options, SceneInputCommand command);

// The options' scene (the demo scene when none) and lights file (the default one when none),
// with the settings of applySceneSettings.
RenderJob sceneJob(const SceneInputOptions& options);
// Sets the job's loading and shadow settings from the options; not its scene or lights.
void applySceneSettings(const SceneInputOptions& options, RenderJob& job);

// The GL device options that `render`, `verify` and `batch` share.
struct DeviceOptions {
  std::string gpu = "auto";  // auto, an EGL device index or cuda:N (resolveGpu)
  bool verbose = false;
  bool stats = false;
};

// Adds --gpu and -v/--verbose, and --stats where `withStats`.
void addDeviceOptions(CLI::App& app, DeviceOptions& options, bool withStats);

// The EGL device index that --gpu names, -1 for the default order (renderer/render/gpu_choice.h),
// under this process's CUDA_VISIBLE_DEVICES. Throws InputError naming the devices that exist.
int resolveGpu(const std::string& gpu);

// A renderer on the options' device; with --verbose it prints the GL platform and version.
// Throws InputError for a --gpu that does not exist.
std::unique_ptr<Renderer> openRenderer(const DeviceOptions& options);

// "omnishadow: warning: ..." on stderr, one line each.
void printWarnings(const std::vector<std::string>& warnings);

// The --stats table on stderr: each stage once, then the total.
void printStats(const StageTimes& times);

// Runs `command(warnings)`; when it throws, prints the warnings gathered so far (they may
// explain the failure) and rethrows.
template <typename Command>
int runPrintingWarnings(Command&& command) {
  std::vector<std::string> warnings;
  try {
    return command(warnings);
  } catch (...) {
    printWarnings(warnings);
    throw;
  }
}

// A number for the JSON outputs: the shortest decimal that reads back as the same float (0.8f
// is 0.8, not 0.800000011920929); null when not finite.
nlohmann::ordered_json jsonNumber(float value);
// The same for a double, written as it is; null when not finite.
nlohmann::ordered_json jsonNumber(double value);
// The shortest decimal that reads back as the same float; "nan", "inf" or "-inf" otherwise.
std::string shortestDecimal(float value);

}  // namespace omnishadow::cli
