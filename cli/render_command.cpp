#include "cli/render_command.h"

#include <GL/glcorearb.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "renderer/camera.h"
#include "renderer/depth_dump.h"
#include "renderer/display_transform.h"
#include "renderer/errors.h"
#include "renderer/gltf_loader.h"
#include "renderer/lights_loader.h"
#include "renderer/output_transaction.h"
#include "renderer/renderer.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
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

// The lights file used when --lights is not given: "<scene stem>.lights.json" beside the scene.
fs::path defaultLightsFile(const fs::path& scene) {
  fs::path candidate = scene.parent_path() / (scene.stem().string() + ".lights.json");
  return fs::exists(candidate) ? candidate : fs::path();
}

// A light so that a scene without any still shows something: at the camera, slightly above.
Light headlight(const ViewCamera& camera, const Bounds& bounds) {
  Light light;
  light.name = "headlight";
  const glm::vec3 up = glm::vec3(glm::inverse(camera.view)[1]);
  const float radius = std::max(bounds.radius(), 1e-3f);
  light.position = camera.eye + up * radius * 0.3f;
  const float distance = glm::length(bounds.center() - light.position);
  light.intensity = distance * distance;  // about 1 lux at the scene center
  light.origin = "default";
  return light;
}

void printStats(const StageTimes& times) {
  std::fprintf(stderr, "stage          ms\n");
  for (const auto& [stage, ms] : times.stages())
    std::fprintf(stderr, "%-12s %8.1f\n", stage.c_str(), ms);
  std::fprintf(stderr, "%-12s %8.1f\n", "total", times.total());
}

struct Outputs {
  std::vector<fs::path> png, exr;
  fs::path aov;
  std::vector<fs::path> all;  // in the order given
};

// Resolves `.`/`..`/symlinks of the existing part, so that two spellings of one file compare
// equal even when the file does not exist yet.
fs::path resolved(const fs::path& path) {
  return fs::weakly_canonical(fs::absolute(path));
}

// No output may overwrite one of `inputs`.
void checkNotAnInput(const Outputs& outputs, const std::vector<std::string>& inputs) {
  for (const fs::path& output : outputs.all)
    for (const std::string& input : inputs)
      if (!input.empty() && resolved(output) == resolved(input))
        throw InputError(output.string() + ": refusing to overwrite an input file");
}

Outputs checkOutputs(const RenderOptions& options) {
  Outputs out;
  std::vector<std::string> outputs = options.outputs;
  if (outputs.empty() && options.aov.empty()) outputs.push_back("render.png");
  for (const std::string& output : outputs) {
    const std::string ext = lowerExtension(output);
    if (ext == ".png") {
      out.png.emplace_back(output);
    } else if (ext == ".exr") {
      out.exr.emplace_back(output);
    } else {
      throw InputError("-o " + output + ": unsupported image format (use .png or .exr)");
    }
    out.all.emplace_back(output);
  }
  if (!options.aov.empty()) {
    if (lowerExtension(options.aov) != ".exr")
      throw InputError("--aov " + options.aov + ": AOVs are written as OpenEXR; use a .exr name");
    out.aov = options.aov;
    out.all.push_back(out.aov);
  }
  for (std::size_t i = 0; i < out.all.size(); ++i) {
    if (fs::is_directory(out.all[i]))
      throw InputError(out.all[i].string() + ": is a folder, expected an image file name");
    for (std::size_t j = 0; j < i; ++j)
      if (resolved(out.all[i]) == resolved(out.all[j]))
        throw InputError(out.all[i].string() + ": the same file is given twice as output");
  }
  return out;
}

AovLayers parseLayers(const std::string& list) {
  AovLayers layers;
  std::istringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name == "all") {
      layers = {true, true, true, true, true, true, true};
    } else if (name == "albedo") {
      layers.albedo = true;
    } else if (name == "roughness") {
      layers.roughness = true;
    } else if (name == "metallic") {
      layers.metallic = true;
    } else if (name == "diffuse") {
      layers.diffuse = true;
    } else if (name == "specular") {
      layers.specular = true;
    } else if (name == "objectId") {
      layers.objectId = true;
    } else if (name == "materialId") {
      layers.materialId = true;
    } else {
      throw InputError("--aov-layers " + list + ": unknown layer \"" + name +
                       "\" (expected albedo, roughness, metallic, diffuse, specular, objectId, "
                       "materialId or all)");
    }
  }
  return layers;
}

DebugView parseDebugView(const std::string& name) {
  if (name == "shadow") return DebugView::Shadow;
  if (name == "depth") return DebugView::Depth;
  if (name == "normals") return DebugView::Normals;
  if (name == "albedo") return DebugView::Albedo;
  if (name == "lightcount") return DebugView::LightCount;
  return DebugView::None;
}

// A folder option (--dump-depth, --light-views) must not name an existing file.
void checkFolderOption(const std::string& option, const std::string& folder) {
  if (!folder.empty() && fs::exists(folder) && !fs::is_directory(folder))
    throw InputError(option + " " + folder + ": is a file, expected a folder");
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
  nlohmann::ordered_json ids;
  ids["objectId"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const MeshInstance& instance = scene.instances[i];
    ids["objectId"].push_back(
        {{"id", i}, {"node", instance.node}, {"mesh", scene.meshes[instance.mesh].name}});
  }
  ids["materialId"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < scene.materials.size(); ++i)
    ids["materialId"].push_back({{"id", i}, {"name", scene.materials[i].name}});
  ids["materialId"].push_back({{"id", scene.materials.size()}, {"name", "(default)"}});
  ids["background"] = -1;
  std::ofstream out(transaction.stage(path));
  out << ids.dump(2) << "\n";
  if (!out.flush()) throw RenderError("cannot write " + path.string());
}

void printWarnings(const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings)
    std::fprintf(stderr, "omnishadow: warning: %s\n", warning.c_str());
}

int render(const RenderOptions& o, std::vector<std::string>& warnings) {
  StageTimes times;
  ScopedStage loadStage(times, "load");

  const fs::path scenePath = o.scene.empty() ? fs::path(OMNISHADOW_DEMO_SCENE) : fs::path(o.scene);
  const fs::path lightsPath = o.lights.empty() ? defaultLightsFile(scenePath) : fs::path(o.lights);
  const Outputs outputs = checkOutputs(o);
  const AovLayers layers = parseLayers(o.aovLayers);
  if (layers.any() && outputs.aov.empty()) throw InputError("--aov-layers: needs --aov FILE.exr");
  const DebugView debugView = parseDebugView(o.debugView);
  if (!o.debugLight.empty() && debugView != DebugView::Depth)
    throw InputError("--debug-light: only used with --debug-view depth");
  checkFolderOption("--dump-depth", o.dumpDepth);
  checkFolderOption("--light-views", o.lightViews);
  checkNotAnInput(outputs, {scenePath.string(), lightsPath.string()});
  if (!std::isfinite(o.exposure))
    throw InputError("--exposure " + std::to_string(o.exposure) +
                     ": expected a finite number of stops");
  CameraRequest cameraRequest;
  cameraRequest.select = o.camera;
  cameraRequest.eye = parseVec3("--eye", o.eye);
  cameraRequest.target = parseVec3("--target", o.target);
  cameraRequest.up = parseVec3("--up", o.up);
  cameraRequest.fovDegrees = o.fov;
  cameraRequest.width = o.width;
  cameraRequest.height = o.height;

  GltfLoadOptions loadOptions;
  loadOptions.sceneIndex = o.sceneIndex;
  const Scene scene = loadGltf(scenePath, loadOptions);
  checkNotAnInput(outputs, scene.inputFiles);
  warnings.insert(warnings.end(), scene.warnings.begin(), scene.warnings.end());
  LightSetup setup;
  if (!lightsPath.empty()) setup = loadLightsFile(lightsPath, warnings);
  std::vector<Light> lights =
      mergeLights(o.noGltfLights ? std::vector<Light>{} : scene.lights, setup.lights);
  const ViewCamera camera = resolveCamera(scene, cameraRequest);
  if (lights.empty()) {
    lights.push_back(headlight(camera, scene.bounds));
    warnings.push_back("no lights in the scene or a lights file: using a headlight at the camera");
  }
  loadStage.stop();

  ScopedStage contextStage(times, "context");
  ContextOptions contextOptions;
  contextOptions.gpuIndex = o.gpu;
  contextOptions.debug = o.verbose;
  Renderer renderer(contextOptions);
  if (o.verbose) {
    std::fprintf(stderr, "omnishadow: %s\nomnishadow: %s\n",
                 renderer.context().platformDescription().c_str(),
                 renderer.context().glDescription().c_str());
    std::fprintf(stderr, "omnishadow: scene %s, camera: %s, %dx%d\n", scenePath.c_str(),
                 camera.description.c_str(), camera.width, camera.height);
  }
  GLint maxCubeSize = 0;
  glGetIntegerv(GL_MAX_CUBE_MAP_TEXTURE_SIZE, &maxCubeSize);
  for (const Light& light : lights)
    if (light.shadow.enabled && light.shadow.resolution > maxCubeSize)
      throw InputError(light.origin + ": light \"" + light.name + "\": shadow.resolution " +
                       std::to_string(light.shadow.resolution) +
                       " exceeds this GL's maximum cube map size " + std::to_string(maxCubeSize));
  contextStage.stop();

  RenderSettings settings;
  settings.shading = o.shading == "phong" ? Shading::Phong : Shading::Pbr;
  settings.aovs = !outputs.aov.empty();
  settings.layers = layers;
  settings.debugView = debugView;
  settings.debugLight = o.debugLight;
  settings.readShadowMaps = !o.dumpDepth.empty();
  settings.lightViewSize = o.lightViews.empty() ? 0 : o.lightViewSize;
  if (settings.readShadowMaps || settings.lightViewSize > 0) checkFileSafeNames(lights);
  Frame frame = renderer.render(scene, lights, setup.ambient, camera, settings, times);
  warnings.insert(warnings.end(), frame.warnings.begin(), frame.warnings.end());

  ScopedStage encodeStage(times, "encode");
  setEncoderThreads(static_cast<int>(std::thread::hardware_concurrency()));
  OutputTransaction transaction;
  if (!outputs.png.empty()) {
    const std::vector<std::uint8_t> srgb = toSrgb8(frame.beauty, o.exposure);
    for (const fs::path& path : outputs.png)
      writePng(transaction.stage(path), camera.width, camera.height, 3, srgb);
  }
  if (!outputs.exr.empty()) {
    const FloatImage exposed = applyExposure(frame.beauty, o.exposure);
    for (const fs::path& path : outputs.exr)
      writeExr(transaction.stage(path), exposed, ExrPixelType::Half);
  }
  if (frame.aovs) writeExr(transaction.stage(outputs.aov), *frame.aovs, ExrPixelType::Float);
  if (layers.objectId || layers.materialId)
    writeIdSidecar(fs::path(outputs.aov).replace_extension(".ids.json"), scene, transaction);
  for (const ShadowMapDump& dump : frame.shadowMaps)
    writePointShadowDump(o.dumpDepth, fileSafeName(dump.light), dump.distances, dump.far,
                         transaction);
  for (const LightView& view : frame.lightViews) {
    const fs::path path =
        fs::path(o.lightViews) /
        (fileSafeName(view.light) + "_" + kCubeFaceNames[static_cast<int>(view.face)] + ".png");
    writePng(transaction.stage(path), view.beauty.width, view.beauty.height, 3,
             toSrgb8(view.beauty, o.exposure));
  }
  transaction.commit();
  encodeStage.stop();

  printWarnings(warnings);
  for (const auto& list : {outputs.png, outputs.exr})
    for (const fs::path& path : list)
      std::printf("wrote %s (%dx%d)\n", path.c_str(), camera.width, camera.height);
  if (!outputs.aov.empty()) std::printf("wrote %s (AOVs)\n", outputs.aov.c_str());
  if (!frame.shadowMaps.empty())
    std::printf("wrote the shadow maps of %zu lights to %s\n", frame.shadowMaps.size(),
                o.dumpDepth.c_str());
  if (!frame.lightViews.empty())
    std::printf("wrote %zu light views to %s\n", frame.lightViews.size(), o.lightViews.c_str());
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
  render->add_flag("--no-gltf-lights", o.noGltfLights,
                   "Ignore the scene's KHR_lights_punctual lights");
  render
      ->add_option("--scene", o.sceneIndex,
                   "Index of the glTF scene to render (default: the file's default scene)")
      ->check(CLI::NonNegativeNumber);
  render->add_option("--camera", o.camera, "glTF camera by name or index (default: the first)");
  render->add_option("--eye", o.eye, "Camera position x,y,z (world units)");
  render->add_option("--target", o.target, "Point the camera looks at, x,y,z");
  render->add_option("--up", o.up, "Camera up vector x,y,z");
  render->add_option("--fov", o.fov, "Vertical field of view in degrees");
  render->add_option("--width", o.width, "Image width in pixels (default 1280)")
      ->check(CLI::Range(1, 16384));
  render
      ->add_option("--height", o.height,
                   "Image height in pixels (default 720, or from the camera's aspect ratio)")
      ->check(CLI::Range(1, 16384));
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
