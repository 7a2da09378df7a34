#include "cli/render_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>
#include <utility>

#include "cli/shared_scene_loads.h"
#include "renderer/core/errors.h"
#include "renderer/output/annotation_masks.h"
#include "renderer/output/camera_sidecar.h"
#include "renderer/output/depth_dump.h"
#include "renderer/output/display_transform.h"
#include "renderer/output/exr_camera.h"
#include "renderer/output/id_index.h"
#include "renderer/output/output_transaction.h"
#include "renderer/render/aov_layer_names.h"
#include "renderer/scene/drawable_check.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_loader.h"
#include "renderer/scene/scene_pose.h"
#include "renderer/view/headlight.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {

fs::path resolvedPath(const fs::path& path) {
  std::error_code error;
  const fs::path absolute = fs::absolute(path);
  const fs::path canonical = fs::weakly_canonical(absolute, error);
  // A name the file system cannot resolve (too long, a symlink loop) is no existing input; the
  // write, or the input's own read, names the problem (found by fuzz_manifest).
  return error ? absolute.lexically_normal() : canonical;
}

bool pathExists(const fs::path& path) {
  std::error_code error;
  return fs::exists(path, error);
}

bool isFolder(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(path, error);
}

namespace {

// A folder option (--dump-depth, --light-views) must not name an existing file.
void checkFolderOption(const std::string& option, const fs::path& folder) {
  if (!folder.empty() && pathExists(folder) && !isFolder(folder))
    throw InputError(option + " " + folder.string() + ": is a file, expected a folder");
}

// Per-light files are named after the lights; two names may not map to one file name.
void checkFileSafeNames(const std::vector<Light>& lights) {
  for (std::size_t i = 0; i < lights.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (fileSafeName(lights[i].name) == fileSafeName(lights[j].name))
        throw InputError("lights \"" + lights[j].name + "\" and \"" + lights[i].name +
                         "\" would write the same files (" + fileSafeName(lights[i].name) +
                         "_*); rename one");
}

// objectId/materialId values and what they stand for, next to the AOV file.
void writeIdSidecar(const fs::path& path, const Scene& scene, OutputTransaction& transaction) {
  const nlohmann::ordered_json ids = idIndex(scene);
  std::ofstream out(transaction.stage(path));
  out << ids.dump(2) << "\n";
  if (!out.flush()) throw RenderError("cannot write " + path.string());
}

}  // namespace

fs::path cameraJsonPath(const RenderJob& job) {
  const fs::path& image = !job.png.empty()   ? job.png.front()
                          : !job.exr.empty() ? job.exr.front()
                                             : job.aov;
  return fs::path(image).replace_extension(".camera.json");
}

fs::path idSidecarPath(const RenderJob& job) {
  return fs::path(job.aov).replace_extension(".ids.json");
}

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

fs::path defaultLightsFile(const fs::path& scene) {
  fs::path candidate = scene.parent_path() / (scene.stem().string() + ".lights.json");
  return pathExists(candidate) ? candidate : fs::path();
}

AovLayers parseLayers(const std::string& list) {
  AovLayers layers;
  std::istringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (!enableAovLayer(layers, name))
      throw InputError("--aov-layers " + list + ": unknown layer \"" + name +
                       "\" (expected albedo, roughness, metallic, diffuse, specular, objectId, "
                       "materialId, occlusion or all)");
  }
  return layers;
}

std::optional<glm::vec3> parseVec3(const std::string& option, const std::string& text) {
  if (text.empty()) return std::nullopt;
  glm::vec3 v;
  std::istringstream in(text);
  char comma1 = 0, comma2 = 0;
  in >> v.x >> comma1 >> v.y >> comma2 >> v.z;
  if (!in || comma1 != ',' || comma2 != ',' || in.peek() != EOF || !std::isfinite(v.x) ||
      !std::isfinite(v.y) || !std::isfinite(v.z))
    throw InputError(option + " " + text +
                     ": expected 3 comma-separated finite numbers, e.g. 0,1.5,4");
  return v;
}

DebugView parseDebugView(const std::string& name) {
  if (name == "shadow") return DebugView::Shadow;
  if (name == "depth") return DebugView::Depth;
  if (name == "normals") return DebugView::Normals;
  if (name == "albedo") return DebugView::Albedo;
  if (name == "lightcount") return DebugView::LightCount;
  if (name == "cascade") return DebugView::Cascade;
  if (name == "occlusion") return DebugView::Occlusion;
  return DebugView::None;
}

std::vector<fs::path> RenderJob::outputFiles() const {
  std::vector<fs::path> all = png;
  all.insert(all.end(), exr.begin(), exr.end());
  if (!aov.empty()) all.push_back(aov);
  if (!aov.empty() && (layers.objectId || layers.materialId)) all.push_back(idSidecarPath(*this));
  if (!masks.empty())
    for (const fs::path& file : annotationMaskFiles(masks)) all.push_back(file);
  if (cameraJson) all.push_back(cameraJsonPath(*this));
  return all;
}

std::vector<fs::path> RenderJob::perLightFiles(const std::vector<Light>& rendered) const {
  std::vector<fs::path> files;
  for (const Light& light : rendered) {
    const std::string name = fileSafeName(light.name);
    if (light.type != LightType::Point) {
      if (!light.shadow.enabled) continue;
      std::vector<std::string> planar;
      if (light.type == LightType::Spot) planar.push_back(name + "_spot");
      for (int c = 0; light.type == LightType::Directional && c < light.shadow.cascades; ++c)
        planar.push_back(name + "_cascade" + std::to_string(c));
      for (const std::string& base : planar) {
        if (!lightViews.empty()) files.push_back(lightViews / (base + ".png"));
        if (!dumpDepth.empty())
          for (const char* ext : {".exr", ".png"}) files.push_back(dumpDepth / (base + ext));
      }
      continue;
    }
    for (const char* face : kCubeFaceNames) {
      if (!lightViews.empty()) files.push_back(lightViews / (name + "_" + face + ".png"));
      if (!dumpDepth.empty() && light.shadow.enabled)
        for (const char* ext : {".exr", ".png"})
          files.push_back(dumpDepth / (name + "_" + face + ext));
    }
    if (!dumpDepth.empty() && light.shadow.enabled) {
      files.push_back(dumpDepth / (name + "_cube.exr"));
      files.push_back(dumpDepth / (name + "_cross.png"));
    }
  }
  return files;
}

void checkNotAnInput(const RenderJob& job, const std::vector<std::string>& inputs) {
  for (const fs::path& output : job.outputFiles())
    for (const std::string& input : inputs)
      if (!input.empty() && resolvedPath(output) == resolvedPath(input))
        throw InputError(output.string() + ": refusing to overwrite an input file");
}

// 1 TiB: beyond any machine this renders on; the bound only has to exclude inf and nan.
constexpr double kMaxMemoryMiB = 1024.0 * 1024.0;

void validateJob(const RenderJob& job) {
  for (const fs::path& path : job.png)
    if (lowerExtension(path) != ".png") throw InputError(path.string() + ": expected a .png name");
  for (const fs::path& path : job.exr)
    if (lowerExtension(path) != ".exr") throw InputError(path.string() + ": expected a .exr name");
  if (!job.aov.empty() && lowerExtension(job.aov) != ".exr")
    throw InputError("--aov " + job.aov.string() +
                     ": AOVs are written as OpenEXR; use a .exr name");
  const std::vector<fs::path> all = job.outputFiles();
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (isFolder(all[i]))
      throw InputError(all[i].string() + ": is a folder, expected an image file name");
    for (std::size_t j = 0; j < i; ++j)
      if (resolvedPath(all[i]) == resolvedPath(all[j]))
        throw InputError(all[i].string() + ": the same file is given twice as output");
  }
  if (job.layers.any() && job.aov.empty()) throw InputError("--aov-layers: needs --aov FILE.exr");
  if (!job.debugLight.empty() && job.debugView != DebugView::Depth &&
      job.debugView != DebugView::Cascade)
    throw InputError("--debug-light: only used with --debug-view depth or cascade");
  checkFolderOption("--dump-depth", job.dumpDepth);
  checkFolderOption("--light-views", job.lightViews);
  // Checked here, not by CLI11's PositiveNumber, which lets nan through (and nan > budget is
  // false: no budget at all) and quotes DBL_MAX in its message.
  if (!(job.maxMemoryMiB > 0.0 && job.maxMemoryMiB <= kMaxMemoryMiB)) {
    std::ostringstream given;
    given << job.maxMemoryMiB;
    throw InputError("--max-memory " + given.str() + ": expected a number of MiB in (0, " +
                     std::to_string(static_cast<int>(kMaxMemoryMiB)) + "]");
  }
  if (!std::isfinite(job.exposure))
    throw InputError("--exposure " + std::to_string(job.exposure) +
                     ": expected a finite number of stops");
  checkNotAnInput(job, {job.scene.string(), job.lights.string()});
}

TimedLoad loadJobTimed(const RenderJob& job, SharedSceneLoads* shared) {
  const auto start = std::chrono::steady_clock::now();
  std::shared_ptr<const Scene> scene = shared ? shared->scene(job) : nullptr;
  TimedLoad load{scene ? loadJob(job, std::move(scene))
                       : loadJob(job, shared ? shared->decodedImages() : nullptr)};
  load.milliseconds = millisecondsSince(start);
  return load;
}

Scene loadJobScene(const RenderJob& job, DecodedImageCache* decodedImages) {
  GltfLoadOptions loadOptions;
  loadOptions.decodedImages = decodedImages;
  loadOptions.sceneIndex = job.sceneIndex;
  loadOptions.materialVariant = job.materialVariant;
  loadOptions.allowExternalUris = job.allowExternalUris;
  return loadGltf(job.scene, loadOptions);
}

namespace {

// The rest of a load once the job has its scene: checks on it, the lights file, the pose, the
// camera and the per-light files.
LoadedJob finishLoad(const RenderJob& job, LoadedJob loaded) {
  checkNotAnInput(job, loaded.scene().inputFiles);
  requireTriangles(loaded.scene());
  loaded.warnings = loaded.scene().warnings;
  if (!job.lights.empty()) loaded.setup = loadLightsFile(job.lights, loaded.warnings);
  const std::vector<std::string> poseWarnings = poseJob(job, job.time, loaded);
  loaded.warnings.insert(loaded.warnings.end(), poseWarnings.begin(), poseWarnings.end());
  if (!loaded.lights.empty() && loaded.lights.front().origin == "default")
    loaded.warnings.push_back(kHeadlightWarning);
  if (!job.dumpDepth.empty() || !job.lightViews.empty()) {
    checkFileSafeNames(loaded.lights);
    // The per-light files must spare the inputs and the job's other outputs too.
    std::vector<std::string> inputs = loaded.scene().inputFiles;
    inputs.push_back(job.lights.string());
    const std::vector<fs::path> files = job.perLightFiles(loaded.lights);
    for (const fs::path& file : files) {
      for (const std::string& input : inputs)
        if (!input.empty() && resolvedPath(file) == resolvedPath(input))
          throw InputError(file.string() + ": refusing to overwrite an input file");
      for (const fs::path& output : job.outputFiles())
        if (resolvedPath(file) == resolvedPath(output))
          throw InputError(file.string() + ": the same file is given twice as output");
    }
  }
  return loaded;
}

}  // namespace

LoadedJob loadJob(const RenderJob& job, DecodedImageCache* decodedImages) {
  LoadedJob loaded;
  loaded.own = loadJobScene(job, decodedImages);
  return finishLoad(job, std::move(loaded));
}

LoadedJob loadJob(const RenderJob& job, std::shared_ptr<const Scene> scene) {
  LoadedJob loaded;
  loaded.shared = std::move(scene);
  return finishLoad(job, std::move(loaded));
}

std::vector<std::string> poseJob(const RenderJob& job, std::optional<double> time,
                                 LoadedJob& loaded) {
  std::vector<std::string> warnings;
  if (time || !loaded.atRest) {
    if (!loaded.own) loaded.own = *loaded.shared;
    warnings = poseSceneChecked(*loaded.own, job.scene.string(), time, job.animation);
    loaded.atRest = !time;
  } else {
    // The loader left the scene at rest: posing it there again would skin it a second time.
    checkPoseRequest(time, job.animation);
  }
  const Scene& scene = loaded.scene();
  loaded.lights =
      mergeLights(job.noGltfLights ? std::vector<Light>{} : scene.lights, loaded.setup.lights);
  loaded.camera = resolveCamera(scene, job.camera);
  // An environment lights the scene by itself; without one, a headlight shows it.
  if (loaded.lights.empty() && !loaded.setup.environment)
    loaded.lights.push_back(headlight(loaded.camera, scene.bounds));
  return warnings;
}

namespace {

RenderSettings renderSettings(const RenderJob& job) {
  RenderSettings settings;
  settings.shading = job.shading;
  settings.aovs = job.aovs || !job.aov.empty();
  settings.layers = job.layers;
  if (!job.masks.empty()) requestObjectIds(settings);  // what masks are made from
  // Masks without an image (`batch --no-png --masks`) need neither shadow maps nor the beauty.
  settings.beauty = !job.png.empty() || !job.exr.empty();
  settings.debugView = job.debugView;
  settings.debugLight = job.debugLight;
  settings.readShadowMaps = !job.dumpDepth.empty();
  settings.lightViewSize = job.lightViews.empty() ? 0 : job.lightViewSize;
  settings.maxShadowMemoryMiB = job.maxMemoryMiB;
  settings.maxAovMemoryMiB = job.maxMemoryMiB;
  settings.shadowPass = job.shadowPass;
  settings.depthPrepass = job.depthPrepass;
  settings.finishEachStage = job.finishEachStage;
  settings.antialiasing = job.antialiasing;
  // Only PNGs of the beauty: the lighting pass may encode their bytes itself.
  if (!job.png.empty() && job.exr.empty()) settings.srgb8Exposure = job.exposure;
  return settings;
}

}  // namespace

void prepareJob(Renderer& renderer, const RenderJob& job, double minimumMiB) {
  if (job.lights.empty()) return;  // the lights are the scene's or a headlight
  // A guess spends little: lights files are kilobytes (the loader reads this one again), and
  // what it prepares is bounded (kPrepareBudgetMiB; the caller's minimumMiB below it).
  constexpr std::uintmax_t kMaxGuessedLightsFileBytes = 1 << 20;
  constexpr double kPrepareBudgetMiB = 256.0;
  std::error_code error;
  const std::uintmax_t size = fs::file_size(job.lights, error);
  if (error || size > kMaxGuessedLightsFileBytes) return;
  LightSetup setup;
  try {
    std::vector<std::string> warnings;
    setup = loadLightsFile(job.lights, warnings);
  } catch (const InputError&) {
    return;  // loadJob() reports it
  }
  // An environment image is read and prefiltered here, beside the scene's load.
  if (setup.environment && drawsLitFrame(renderSettings(job)))
    renderer.prepareEnvironment(*setup.environment);
  const std::vector<Light> lights = mergeLights({}, setup.lights);
  if (lights.empty()) return;
  try {
    renderer.prepare(lights, job.camera.width.value_or(kDefaultWidth),
                     job.camera.height.value_or(kDefaultHeight), renderSettings(job),
                     kPrepareBudgetMiB, minimumMiB);
  } catch (const RenderError&) {
    // The render meets it again, after the load, whose errors come first.
  }
}

std::size_t frameMemoryEstimate(const Renderer& renderer, const RenderJob& job,
                                const LoadedJob& loaded) {
  double bytes =
      renderer.frameBytes(loaded.scene(), loaded.lights, loaded.camera, renderSettings(job));
  for (const Image& image : loaded.scene().images)
    bytes += static_cast<double>(image.rgba.size()) * 4.0 / 3.0;
  for (const Mesh& mesh : loaded.scene().meshes) bytes += static_cast<double>(meshBytes(mesh));
  return static_cast<std::size_t>(bytes);
}

Frame renderJob(Renderer& renderer, const RenderJob& job, const LoadedJob& loaded,
                StageTimes& times) {
  // Refused before the frame is drawn, not after.
  if (!job.masks.empty()) checkMaskInstances(loaded.scene(), job.scene.string());
  return renderer.render(loaded.scene(), loaded.lights, Ambience(loaded.setup), loaded.camera,
                         renderSettings(job), times);
}

std::vector<fs::path> writeJobOutputs(const RenderJob& job, const LoadedJob& loaded,
                                      const Frame& frame) {
  OutputTransaction transaction;
  std::vector<fs::path> written;
  auto stage = [&](const fs::path& path) {
    written.push_back(path);
    return transaction.stage(path);
  };
  // The masks (every instance rasterized alone on the CPU, the pixels counted) are made and
  // encoded on a second thread while this one encodes the beauty; their errors still come
  // where they did.
  std::future<EncodedAnnotationMasks> masks;
  if (!job.masks.empty())
    masks = std::async(std::launch::async, [&] {
      return encodeAnnotationMasks(
          annotationMasks(loaded.scene(), loaded.camera, objectIdImage(frame)));
    });
  if (frame.srgb8) {
    for (const fs::path& path : job.png)
      writePng(stage(path), frame.srgb8->width, frame.srgb8->height, 3, frame.srgb8->rgb);
  } else if (!job.png.empty()) {
    const std::vector<std::uint8_t> srgb = toSrgb8(frame.beauty, job.exposure);
    for (const fs::path& path : job.png)
      writePng(stage(path), frame.beauty.width, frame.beauty.height, 3, srgb);
  }
  const ExrCameraAttributes camera = exrCameraAttributes(loaded.camera);
  if (!job.exr.empty()) {
    const FloatImage exposed = applyExposure(frame.beauty, job.exposure);
    for (const fs::path& path : job.exr)
      writeExr(stage(path), exposed, ExrPixelType::Half, &camera);
  }
  if (frame.aovs && !job.aov.empty())
    writeExr(stage(job.aov), *frame.aovs, ExrPixelType::Float, &camera);
  if (job.cameraJson) {
    std::ofstream out(stage(cameraJsonPath(job)));
    out << cameraSidecar(loaded.camera, loaded.scene(), job.time).dump(2) << "\n";
    if (!out.flush()) throw RenderError("cannot write " + cameraJsonPath(job).string());
  }
  if (!job.masks.empty()) {
    for (const fs::path& file : annotationMaskFiles(job.masks)) written.push_back(file);
    writeAnnotationMasks(masks.get(), job.masks, transaction);
  }
  if (job.layers.objectId || job.layers.materialId) {
    written.push_back(idSidecarPath(job));
    writeIdSidecar(idSidecarPath(job), loaded.scene(), transaction);
  }
  for (const ShadowMapDump& dump : frame.shadowMaps)
    writePointShadowDump(job.dumpDepth, fileSafeName(dump.light), dump.distances, dump.far,
                         transaction);
  for (const PlanarShadowMapDump& dump : frame.planarShadowMaps)
    writePlanarShadowDump(job.dumpDepth, fileSafeName(dump.light) + "_" + dump.planar,
                          dump.resolution, dump.distances, dump.far, transaction);
  for (const LightView& view : frame.lightViews) {
    const std::string suffix =
        view.planar.empty() ? kCubeFaceNames[static_cast<int>(view.face)] : view.planar;
    const fs::path path = job.lightViews / (fileSafeName(view.light) + "_" + suffix + ".png");
    writePng(stage(path), view.beauty.width, view.beauty.height, 3,
             toSrgb8(view.beauty, job.exposure));
  }
  transaction.commit();
  return written;
}

}  // namespace omnishadow::cli
