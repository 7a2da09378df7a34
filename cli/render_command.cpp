#include "cli/render_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <thread>

#include "cli/render_job.h"
#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"
#include "renderer/render/renderer.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

void printStats(const StageTimes& times) {
  std::fprintf(stderr, "stage          ms\n");
  for (const auto& [stage, ms] : times.stages())
    std::fprintf(stderr, "%-12s %8.1f\n", stage.c_str(), ms);
  std::fprintf(stderr, "%-12s %8.1f\n", "total", times.total());
}

void printWarnings(const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings)
    std::fprintf(stderr, "omnishadow: warning: %s\n", warning.c_str());
}

// The command line as a job; checks everything that needs no file reading.
RenderJob jobFromOptions(const RenderOptions& o) {
  RenderJob job;
  job.scene = o.scene.empty() ? fs::path(OMNISHADOW_DEMO_SCENE) : fs::path(o.scene);
  job.lights = o.lights.empty() ? defaultLightsFile(job.scene) : fs::path(o.lights);
  job.noGltfLights = o.noGltfLights;
  job.allowExternalUris = o.allowExternalUris;
  job.maxMemoryMiB = o.maxMemoryMiB;
  job.shadowPass = parseShadowPassStrategy(o.shadowPass);
  job.sceneIndex = o.sceneIndex;
  std::vector<std::string> outputs = o.outputs;
  if (outputs.empty() && o.aov.empty()) outputs.push_back("render.png");
  for (const std::string& output : outputs) {
    const std::string ext = lowerExtension(output);
    if (ext == ".png") {
      job.png.emplace_back(output);
    } else if (ext == ".exr") {
      job.exr.emplace_back(output);
    } else {
      throw InputError("-o " + output + ": unsupported image format (use .png or .exr)");
    }
  }
  job.aov = o.aov;
  job.layers = parseLayers(o.aovLayers);
  job.exposure = o.exposure;
  job.shading = o.shading == "phong" ? Shading::Phong : Shading::Pbr;
  job.debugView = parseDebugView(o.debugView);
  job.debugLight = o.debugLight;
  job.dumpDepth = o.dumpDepth;
  job.lightViews = o.lightViews;
  job.lightViewSize = o.lightViewSize;
  validateJob(job);
  job.camera = cameraRequest(o.view);
  return job;
}

int render(const RenderOptions& o, std::vector<std::string>& warnings) {
  StageTimes times;
  ScopedStage loadStage(times, "load");
  const RenderJob job = jobFromOptions(o);
  LoadedJob loaded = loadJob(job);
  warnings = loaded.warnings;
  loadStage.stop();

  ScopedStage contextStage(times, "context");
  ContextOptions contextOptions;
  contextOptions.gpuIndex = o.gpu;
  contextOptions.debug = o.verbose;
  Renderer renderer(contextOptions);
  if (o.verbose) {
    std::fprintf(stderr, "omnishadow: %s\nomnishadow: %s\n",
                 renderer.platformDescription().c_str(),
                 renderer.glDescription().c_str());
    std::fprintf(stderr, "omnishadow: scene %s, camera: %s, %dx%d\n", job.scene.c_str(),
                 loaded.camera.description.c_str(), loaded.camera.width, loaded.camera.height);
  }
  contextStage.stop();

  const Frame frame = renderJob(renderer, job, loaded, times);
  warnings.insert(warnings.end(), frame.warnings.begin(), frame.warnings.end());

  ScopedStage encodeStage(times, "encode");
  setEncoderThreads(static_cast<int>(std::thread::hardware_concurrency()));
  writeJobOutputs(job, loaded, frame);
  encodeStage.stop();

  printWarnings(warnings);
  for (const auto& list : {job.png, job.exr})
    for (const fs::path& path : list)
      std::printf("wrote %s (%dx%d)\n", path.c_str(), loaded.camera.width, loaded.camera.height);
  if (!job.aov.empty()) std::printf("wrote %s (AOVs)\n", job.aov.c_str());
  if (!frame.shadowMaps.empty())
    std::printf("wrote the shadow maps of %zu lights to %s\n", frame.shadowMaps.size(),
                job.dumpDepth.c_str());
  if (!frame.lightViews.empty())
    std::printf("wrote %zu light views to %s\n", frame.lightViews.size(), job.lightViews.c_str());
  if (o.stats) printStats(times);
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, RenderOptions& o) {
  CLI::App* render = app.add_subcommand(
      "render", "Render a glTF scene (default: the built-in demo room) to PNG/EXR images");
  render->add_option("scene", o.scene, "glTF 2.0 scene (.gltf or .glb); default: the demo scene");
  render->add_option("-l,--lights", o.lights,
                     "Lights file (JSON); default: <scene>.lights.json next to the scene, if any");
  render
      ->add_option("--shadow-pass", o.shadowPass,
                   "How point-light cube maps are rendered: six, geometry, instanced or auto "
                   "(default: the fastest measured on this driver)")
      ->check(CLI::IsMember({"auto", "six", "geometry", "instanced"}));
  render
      ->add_option("--max-memory", o.maxMemoryMiB,
                   "Memory the shadow maps of one frame may use, in MiB (default 4096)")
      ->check(CLI::PositiveNumber);
  render->add_flag("--allow-external-uris", o.allowExternalUris,
                   "Let the scene read buffers and images outside its own folder");
  render->add_flag("--no-gltf-lights", o.noGltfLights,
                   "Ignore the scene's KHR_lights_punctual lights");
  render
      ->add_option("--scene", o.sceneIndex,
                   "Index of the glTF scene to render (default: the file's default scene)")
      ->check(CLI::NonNegativeNumber);
  addViewOptions(*render, o.view);
  render
      ->add_option("-o,--output", o.outputs,
                   "Output image: .png (8-bit sRGB) or .exr (linear half RGBA); repeatable "
                   "(default: render.png)")
      ->allow_extra_args(false);
  render->add_option("--aov", o.aov,
                     "Write AOVs (position, normal, distance, per-light visibility) to this .exr");
  render->add_option("--aov-layers", o.aovLayers,
                     "Extra AOV layers, comma-separated: albedo, roughness, metallic, diffuse, "
                     "specular, objectId, materialId, or all (needs --aov)");
  render->add_option(
      "--dump-depth", o.dumpDepth,
      "Write every shadow map to this folder (EXR distances, PNG previews, cube map, cross)");
  render->add_option(
      "--light-views", o.lightViews,
      "Write the lit scene seen from each cube face of each point light to this folder");
  render
      ->add_option("--light-view-size", o.lightViewSize,
                   "Size of the --light-views images (default 512)")
      ->check(CLI::Range(1, 16384));
  render
      ->add_option("--debug-view", o.debugView,
                   "Replace the beauty by: shadow, depth, normals, albedo or lightcount")
      ->check(CLI::IsMember({"none", "shadow", "depth", "normals", "albedo", "lightcount"}));
  render->add_option("--debug-light", o.debugLight,
                     "Light shown by --debug-view depth (default: the first shadowed point light)");
  render->add_option("--exposure", o.exposure,
                     "Exposure in stops applied to the beauty images (default 0)");
  render->add_option("--shading", o.shading, "pbr (glTF metallic-roughness) or phong (Blinn-Phong)")
      ->check(CLI::IsMember({"pbr", "phong"}));
  render
      ->add_option("--gpu", o.gpu,
                   "EGL device index to render on (default: first hardware device, else software)")
      ->check(CLI::NonNegativeNumber);
  render->add_flag("-v,--verbose", o.verbose,
                   "Print the GL platform, vendor, renderer, version and GL debug messages");
  render->add_flag("--stats", o.stats, "Print the time of each stage to stderr");
}

int runRender(const RenderOptions& o) {
  std::vector<std::string> warnings;
  try {
    return render(o, warnings);
  } catch (...) {
    printWarnings(warnings);  // they may explain the failure
    throw;
  }
}

}  // namespace omnishadow::cli
