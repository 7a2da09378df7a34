#include "python/src/py_renderer.h"

#include <pybind11/stl.h>

#include <cmath>
#include <sstream>

#include "renderer/core/errors.h"
#include "renderer/render/aov_layer_names.h"
#include "renderer/view/headlight.h"

namespace py = pybind11;

namespace omnishadow::python {
namespace {

// The AOV layer names of --aov-layers; the fixed channels' names are accepted too (they are
// always there).
AovLayers aovLayers(const py::object& aovs) {
  AovLayers layers;
  for (const std::string& name : aovs.cast<std::vector<std::string>>()) {
    const bool fixed = name == "P" || name == "N" || name == "Z" || name == "visibility";
    if (!enableAovLayer(layers, name) && !fixed)
      throw InputError("aovs: unknown layer \"" + name +
                       "\" (expected albedo, roughness, metallic, diffuse, specular, objectId, "
                       "materialId, occlusion or all; P, N, Z and visibility are always there)");
  }
  return layers;
}

RenderSettings renderSettings(const PyRenderOptions& o) {
  RenderSettings settings;
  if (o.shading != "pbr" && o.shading != "phong")
    throw InputError("shading " + o.shading + ": expected pbr or phong");
  settings.shading = o.shading == "phong" ? Shading::Phong : Shading::Pbr;
  settings.aovs = !o.aovs.is_none();
  if (settings.aovs) settings.layers = aovLayers(o.aovs);
  if (o.masks) requestObjectIds(settings);
  settings.beauty = o.beauty;
  if (!std::isfinite(o.exposure))
    throw InputError("exposure " + std::to_string(o.exposure) +
                     ": expected a finite number of stops");
  settings.readShadowMaps = o.shadowMaps;
  if (!(o.maxMemoryMiB > 0))
    throw InputError("max_memory " + std::to_string(o.maxMemoryMiB) + ": expected MiB > 0");
  settings.maxShadowMemoryMiB = o.maxMemoryMiB;
  settings.maxAovMemoryMiB = o.maxMemoryMiB;
  if (!isShadowPassStrategyName(o.shadowPass))
    throw InputError("shadow_pass " + o.shadowPass +
                     ": expected auto, six, geometry, instanced or batched");
  settings.shadowPass = parseShadowPassStrategy(o.shadowPass);
  if (!isDepthPrepassName(o.depthPrepass))
    throw InputError("depth_prepass " + o.depthPrepass + ": expected auto, on or off");
  settings.depthPrepass = parseDepthPrepass(o.depthPrepass);
  if (!isFinishEachStageName(o.finishEachStage))
    throw InputError("finish_each_stage " + o.finishEachStage + ": expected auto, on or off");
  settings.finishEachStage = parseFinishEachStage(o.finishEachStage);
  settings.antialiasing = o.antialiasing;  // checked by planFrame, with the CLI's message
  return settings;
}

}  // namespace

PyRenderer::PyRenderer(const py::object& gpu, bool verbose) : owner_(std::this_thread::get_id()) {
  ContextOptions options;
  if (!gpu.is_none()) {
    const long long index = gpu.cast<long long>();
    if (index < 0 || index > 1'000'000)
      throw InputError("gpu " + std::to_string(index) + ": expected an EGL device index >= 0");
    options.gpuIndex = static_cast<int>(index);
  }
  options.debug = verbose;
  py::gil_scoped_release release;
  renderer_ = std::make_unique<Renderer>(options);
}

void PyRenderer::checkThread(const char* what) const {
  if (std::this_thread::get_id() == owner_) return;
  throw RenderError(std::string("Renderer.") + what +
                    ": called from another thread than the one that created the Renderer; its "
                    "GL context belongs to that thread (create one Renderer per thread)");
}

std::string PyRenderer::platform() const {
  checkThread("platform");
  return renderer_->platformDescription();
}

std::string PyRenderer::gl() const {
  checkThread("gl");
  return renderer_->glDescription();
}

PyFrame PyRenderer::render(const PyScene& scene, const py::object& lights,
                           const PyRenderOptions& options) {
  checkThread("render");
  if (!scene.scene) throw InputError("render: scene is not loaded (use omnishadow.load_scene)");
  PyLights loadedLights;
  if (py::isinstance<PyLights>(lights))
    loadedLights = lights.cast<PyLights>();
  else if (!lights.is_none())
    loadedLights = loadLights(lights, "lights");
  const RenderSettings settings = renderSettings(options);
  const CameraRequest request = cameraRequest(options.camera, options.width, options.height);

  PyFrame out;
  out.scene = scene.scene;
  out.time = scene.time;
  out.exposure = options.exposure;
  out.warnings = scene.scene->warnings;
  out.warnings.insert(out.warnings.end(), loadedLights.warnings.begin(),
                      loadedLights.warnings.end());
  {
    py::gil_scoped_release release;
    ScopedStage loadStage(out.times, "load");
    std::vector<Light> merged =
        mergeLights(options.noGltfLights ? std::vector<Light>{} : scene.scene->lights,
                    loadedLights.setup.lights);
    out.camera = resolveCamera(*scene.scene, request);
    if (merged.empty() && !loadedLights.setup.environment) {
      merged.push_back(headlight(out.camera, scene.scene->bounds));
      out.warnings.push_back(kHeadlightWarning);
    }
    loadStage.stop();
    out.frame = renderer_->render(*scene.scene, merged, Ambience(loadedLights.setup), out.camera,
                                  settings, out.times);
    out.lights = std::move(merged);
  }
  out.warnings.insert(out.warnings.end(), out.frame.warnings.begin(), out.frame.warnings.end());
  return out;
}

}  // namespace omnishadow::python
