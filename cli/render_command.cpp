#include "cli/render_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <future>
#include <sstream>
#include <thread>

#include "cli/common_options.h"
#include "cli/malloc_heap.h"
#include "cli/memory_warmup.h"
#include "cli/render_job.h"
#include "cli/steady_frames.h"
#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"
#include "renderer/render/renderer.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

// The most a render's warm-up may fault in: a 1280x720 frame's targets, readback and PNG
// (about 40 MB), a few 1024^2 cube maps (24 MB each) and the scene's textures. Only what idle
// time allows is touched; the untouched rest costs no memory. With huge pages idle time
// touches all of it, and 256 MB made single renders slower than 128 (more to zero): process
// wall, 9 interleaved rounds, Sundial 178 against 195 ms, test_room 223 against 243.
constexpr std::size_t kWarmupBytes = std::size_t{128} << 20;

// The command line as a job; checks everything that needs no file reading.
RenderJob jobFromOptions(const RenderOptions& o) {
  RenderJob job = sceneJob(o.input);
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
  job.masks = o.masks;
  job.antialiasing = o.antialiasing;
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
  if (isFrameSet(o.frames)) {
    // Many frames of one scene: no warm-up ahead of the first, but the heap set up as for one.
    setUpMallocHeap();
    RenderJob pattern = jobFromOptions(o);
    pattern.cameraJson = o.frames.cameraJson;
    return renderFrameSet(pattern, o.frames, o.device, warnings);
  }
  StageTimes times;
  const auto start = std::chrono::steady_clock::now();
  RenderJob job = jobFromOptions(o);
  job.cameraJson = o.frames.cameraJson;
  validateJob(job);
  // The scene loads on a second thread while this one opens the GL context (30 ms of llvmpipe
  // and driver set-up), so a process pays for the longer of the two, not both. A scene that
  // cannot load is still what is reported when both fail, as when they ran in turn. --stats
  // shows the load's own time and the context's time beyond it.
  MemoryWarmup warmup(kWarmupBytes);
  std::future<TimedLoad> loading =
      std::async(std::launch::async, [&job] { return loadJobTimed(job); });
  std::unique_ptr<Renderer> renderer;
  std::exception_ptr contextError;
  try {
    renderer = openRenderer(o.device);
  } catch (...) {
    contextError = std::current_exception();
  }
  // While the scene is still loading, this thread allocates and clears what the frame will
  // need. When it has loaded already, nothing would overlap: the frame allocates its textures
  // itself, from the pages the warm-up touched. Where the toucher has not measured a fresh 4 KiB
  // page under kDearPageFaultMicroseconds (its CPU time; a toucher that had no core to measure
  // on by then counts as dear), only shadow maps and targets of more than half the warm-up's
  // block: smaller ones the frame takes from the warm-up's pages, which preparing would leave for
  // fresh ones faulted in on this thread; larger ones outgrow the block and are faulted in by
  // someone anyway. Measured where a fault cost 10-12 us, before the heap above the block asked
  // for huge pages (issue 19 in docs/performance.md): preparing Sundial's 49 MiB took 125-150 ms
  // whenever the context was ready a little before the load; the 250k-triangle bench room's
  // 121 MiB took as long prepared as not. With the heap in huge pages, preparing everything made
  // Avocado 8% quicker and DamagedHelmet 15% slower: the rule stays.
  if (renderer && loading.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    const double fault = warmup.pageFaultMicroseconds();
    const bool cheap = fault > 0.0 && fault < kDearPageFaultMicroseconds;
    prepareJob(*renderer, job,
               warmup.active() && !cheap ? static_cast<double>(kWarmupBytes >> 20) / 2.0 : 0.0);
  }
  auto [loaded, loadMilliseconds] = loading.get();
  warmup.finish(renderer ? frameMemoryEstimate(*renderer, job, loaded) : 0);
  if (contextError) std::rethrow_exception(contextError);
  warnings = loaded.warnings;
  times.add("load", loadMilliseconds);
  times.add("context", std::max(0.0, millisecondsSince(start) - loadMilliseconds));
  if (o.device.verbose) {
    std::fprintf(stderr, "omnishadow: scene %s, camera: %s, %dx%d\n", job.scene.c_str(),
                 loaded.camera.description.c_str(), loaded.camera.width, loaded.camera.height);
    if (warmup.active())
      std::fprintf(stderr, "omnishadow: memory: a fresh 4 KiB page took %.1f us; %s\n",
                   warmup.heapAbove().pageFaultMicroseconds,
                   warmup.heapAbove().hugePages ? "the heap above the warm-up asks for huge pages"
                                                : "4 KiB pages above the warm-up");
  }

  const Frame frame = renderJob(*renderer, job, loaded, times);
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
  if (!job.masks.empty()) std::printf("wrote %s.* (annotation masks)\n", job.masks.c_str());
  if (job.cameraJson) std::printf("wrote %s (camera)\n", cameraJsonPath(job).c_str());
  if (!frame.shadowMaps.empty())
    std::printf("wrote the shadow maps of %zu lights to %s\n", frame.shadowMaps.size(),
                job.dumpDepth.c_str());
  if (!frame.planarShadowMaps.empty())
    std::printf("wrote %zu spot maps and cascades to %s\n", frame.planarShadowMaps.size(),
                job.dumpDepth.c_str());
  if (!frame.lightViews.empty())
    std::printf("wrote %zu light views to %s\n", frame.lightViews.size(), job.lightViews.c_str());
  if (o.device.stats) printStats(times);
  if (o.repeat > 0) printSteadyFrames(*renderer, job, loaded, o.repeat);
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, RenderOptions& o) {
  CLI::App* render = app.add_subcommand(
      "render", "Render a glTF scene (default: the built-in demo room) to PNG/EXR images");
  addSceneInputOptions(*render, o.input, SceneInputCommand::Render);
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
                     "specular, objectId, materialId, occlusion, or all (needs --aov)");
  render->add_option("--masks", o.masks,
                     "Write annotation masks: STEM.instances.png and STEM.semantic.png (16-bit, "
                     "0 = background) and STEM.masks.json (ids, classes, boxes, visible "
                     "fractions)");
  render
      ->add_option("--aa", o.antialiasing,
                   "Anti-aliased beauty: 1 (default), 4, 8 or 16 samples per pixel; AOVs, ids, "
                   "masks, depth and visibility stay exact (the pixel center's surface)")
      ->check(CLI::IsMember({1, 4, 8, 16}));
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
      ->add_option(
          "--debug-view", o.debugView,
          "Replace the beauty by: shadow, depth, normals, albedo, lightcount, cascade or occlusion")
      ->check(CLI::IsMember(
          {"none", "shadow", "depth", "normals", "albedo", "lightcount", "cascade", "occlusion"}));
  render->add_option(
      "--debug-light", o.debugLight,
      "Light shown by --debug-view depth (default: the first shadowed light, of any type) or "
      "cascade (default: the first shadowed directional light)");
  render
      ->add_option("--repeat", o.repeat,
                   "Time N more frames of the same job after the one written (lights moved by "
                   "1 mm every other frame, so every frame renders its shadow maps) and print "
                   "their median stage times to stderr as \"steady ...\" lines")
      ->check(CLI::Range(0, 100000));
  render->add_option("--exposure", o.exposure,
                     "Exposure in stops applied to the beauty images (default 0)");
  render->add_option("--shading", o.shading, "pbr (glTF metallic-roughness) or phong (Blinn-Phong)")
      ->check(CLI::IsMember({"pbr", "phong"}));
  addDeviceOptions(*render, o.device, true);
  addFrameSetOptions(*render, o.frames);
}

int runRender(const RenderOptions& o) {
  return runPrintingWarnings(
      [&](std::vector<std::string>& warnings) { return render(o, warnings); });
}

}  // namespace omnishadow::cli
