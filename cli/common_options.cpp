#include "cli/common_options.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "cli/render_job.h"
#include "renderer/render/gpu_choice.h"
#include "renderer/render/gpu_devices.h"
#include "renderer/render/renderer.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {

void addSceneInputOptions(CLI::App& app, SceneInputOptions& o, SceneInputCommand command) {
  const bool renders = command != SceneInputCommand::Info;
  if (command == SceneInputCommand::Info)
    app.add_option("scene", o.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
  else if (command != SceneInputCommand::Batch)
    app.add_option("scene", o.scene, "glTF 2.0 scene (.gltf or .glb); default: the demo scene");
  app.add_option(
      "-l,--lights", o.lights,
      command == SceneInputCommand::Batch
          ? "One lights file for every scene (default: <scene>.lights.json, else "
            "lights.json in the scene's folder)"
          : "Lights file (JSON); default: <scene>.lights.json next to the scene, if any");
  if (command == SceneInputCommand::Render || command == SceneInputCommand::Batch) {
    app.add_option("--shadow-pass", o.shadowPass,
                   "How point-light cube maps are rendered: six, geometry, instanced, batched "
                   "(one pass for the frame's point lights) or auto (default; six: the fastest "
                   "measured on llvmpipe; on NVIDIA H100 and H200 GPUs within 10% of instanced, "
                   "1.6-2.9x faster than geometry, and 1.1-1.2x faster than batched with 256 "
                   "lights at 512^2 and 1024^2)")
        ->check(CLI::IsMember({"auto", "six", "geometry", "instanced", "batched"}));
    const CLI::IsMember autoOnOff({"auto", "on", "off"});
    app.add_option("--depth-prepass", o.depthPrepass,
                   "Whether the opaque surfaces write their depth before they are shaded, so "
                   "that each pixel is shaded once: on, off or auto (default; on llvmpipe drawn "
                   "unless little overdraw for its triangles is estimated on the CPU for the "
                   "scene and camera; off on GPUs). The picture is the same")
        ->check(autoOnOff);
    app.add_option("--finish-each-stage", o.finishEachStage,
                   "Whether the GPU finishes the upload and the shadow maps before the lighting "
                   "is submitted, so that --stats gives each stage its own GPU work: on, off "
                   "(the lighting's CPU work runs while the GPU draws the shadow maps, and the "
                   "lighting's time holds what is left of their GPU work) or auto (default; on "
                   "llvmpipe, off on GPUs). The picture is the same")
        ->check(autoOnOff);
  }
  if (renders)
    app.add_option("--max-memory", o.maxMemoryMiB,
                   "Memory the shadow maps of one frame may use, in MiB (default 4096)");
  app.add_flag("--allow-external-uris", o.allowExternalUris,
               "Let the scene read buffers and images outside its own folder");
  if (renders)
    app.add_flag("--no-gltf-lights", o.noGltfLights,
                 "Ignore the scene's KHR_lights_punctual lights");
  app.add_option("--scene", o.sceneIndex,
                 renders ? "Index of the glTF scene to render (default: the file's default scene)"
                         : "Index of the glTF scene to describe (default: the file's default "
                           "scene)")
      ->check(CLI::NonNegativeNumber);
  app.add_option(
      "--variant", o.materialVariant,
      std::string(renders ? "Material variant to draw" : "Material variant to describe") +
          " (KHR_materials_variants): a name or an index (default: the primitives' own "
          "materials)");
  if (renders) {
    app.add_option("--time", o.time,
                   "Pose the scene at this time in seconds: its animations play (default: the "
                   "rest pose; skins and default morph weights apply either way)");
    app.add_option("--animation", o.animation,
                   "Animations that play with --time: a name, an index or all (default: all)");
  }
}

RenderJob sceneJob(const SceneInputOptions& o) {
  RenderJob job;
  job.scene = o.scene.empty() ? fs::path(OMNISHADOW_DEMO_SCENE) : fs::path(o.scene);
  job.lights = o.lights.empty() ? defaultLightsFile(job.scene) : fs::path(o.lights);
  applySceneSettings(o, job);
  return job;
}

void applySceneSettings(const SceneInputOptions& o, RenderJob& job) {
  job.noGltfLights = o.noGltfLights;
  job.allowExternalUris = o.allowExternalUris;
  job.maxMemoryMiB = o.maxMemoryMiB;
  job.shadowPass = parseShadowPassStrategy(o.shadowPass);
  job.depthPrepass = parseDepthPrepass(o.depthPrepass);
  job.finishEachStage = parseFinishEachStage(o.finishEachStage);
  job.sceneIndex = o.sceneIndex;
  job.materialVariant = o.materialVariant;
  job.time = o.time;
  job.animation = o.animation;
}

void addDeviceOptions(CLI::App& app, DeviceOptions& o, bool withStats) {
  app.add_option("--gpu", o.gpu,
                 "EGL device to render on: an index (see `omnishadow devices`), cuda:N, or auto "
                 "(default: the first CUDA_VISIBLE_DEVICES device when set, else the first "
                 "hardware device, else software)");
  app.add_flag("-v,--verbose", o.verbose,
               "Print the GL platform, vendor, renderer, version and GL debug messages");
  if (withStats) app.add_flag("--stats", o.stats, "Print the time of each stage to stderr");
}

int resolveGpu(const std::string& gpu) {
  const GpuRequest request = parseGpuRequest(gpu);
  const char* visible = std::getenv("CUDA_VISIBLE_DEVICES");
  // Listing the devices loads every EGL driver: not needed for the default order.
  if (request.kind == GpuRequest::Kind::Auto && visible == nullptr) return -1;
  return chooseGpu(request, listGpuDevices(false),
                   visible ? std::optional<std::string>(visible) : std::nullopt);
}

std::unique_ptr<Renderer> openRenderer(const DeviceOptions& o) {
  ContextOptions context;
  context.gpuIndex = resolveGpu(o.gpu);
  context.debug = o.verbose;
  auto renderer = std::make_unique<Renderer>(context);
  if (o.verbose)
    std::fprintf(stderr, "omnishadow: %s\nomnishadow: %s\n",
                 renderer->platformDescription().c_str(), renderer->glDescription().c_str());
  return renderer;
}

void printWarnings(const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings)
    std::fprintf(stderr, "omnishadow: warning: %s\n", warning.c_str());
}

void printStats(const StageTimes& times) {
  std::fprintf(stderr, "stage          ms\n");
  for (const auto& [stage, ms] : times.stages())
    std::fprintf(stderr, "%-12s %8.1f\n", stage.c_str(), ms);
  std::fprintf(stderr, "%-12s %8.1f\n", "total", times.total());
  // Parts of the stages above, so after the total: each GL stage's wait for the GPU.
  for (const auto& [stage, ms] : times.waits())
    std::fprintf(stderr, "%-12s %8.1f\n", (kGpuWaitPrefix + stage).c_str(), ms);
}

std::string shortestDecimal(float value) {
  if (!std::isfinite(value)) return std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

nlohmann::ordered_json jsonNumber(float value) {
  if (!std::isfinite(value)) return nullptr;
  return std::strtod(shortestDecimal(value).c_str(), nullptr);
}

nlohmann::ordered_json jsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

}  // namespace omnishadow::cli
