// Renderer.verify(): the exact ray-cast shadow reference against a render's visibility AOVs,
// as Python data (the numbers of `omnishadow verify --json`).
#include <pybind11/stl.h>

#include <cmath>

#include "python/src/py_renderer.h"
#include "renderer/core/errors.h"
#include "renderer/verify/shadow_reference.h"
#include "renderer/verify/shadow_verification.h"
#include "renderer/view/shadow_plan.h"

namespace py = pybind11;

namespace omnishadow::python {
namespace {

py::dict counts(const ClassCounts& c) {
  auto rate = [&](double r) { return c.evaluated > 0 ? py::object(py::float_(r)) : py::none(); };
  py::dict d;
  d["evaluated"] = c.evaluated;
  d["agree"] = c.agree;
  d["falseShadow"] = c.falseShadow;
  d["falseLight"] = c.falseLight;
  d["agreementRate"] = rate(c.agreementRate());
  d["falseShadowRate"] = rate(c.falseShadowRate());
  d["falseLightRate"] = rate(c.falseLightRate());
  return d;
}

py::dict skipped(const SkipCounts& s) {
  py::dict d;
  d["background"] = s.background;
  d["outOfRange"] = s.outOfRange;
  d["outsideCone"] = s.outsideCone;
  d["facingAway"] = s.facingAway;
  d["grazing"] = s.grazing;
  d["beyondShadowFar"] = s.beyondShadowFar;
  d["unlit"] = s.unlit;
  return d;
}

}  // namespace

py::dict PyRenderer::verify(const PyScene& scene, const py::object& lights,
                            const PyRenderOptions& options, const std::string& lightName,
                            const PyVerifyOptions& o) {
  const int side = static_cast<int>(std::lround(std::sqrt(o.sourceSamples)));
  if (o.sourceSamples < 1 || side * side != o.sourceSamples)
    throw InputError("source_samples " + std::to_string(o.sourceSamples) +
                     ": expected a square number (a stratified n x n pattern), e.g. 16, 64, 256");
  std::optional<double> maxError;
  if (!o.maxError.is_none()) maxError = o.maxError.cast<double>();
  PyRenderOptions renderOptions = options;
  if (renderOptions.aovs.is_none()) renderOptions.aovs = py::list();
  const PyFrame frame = render(scene, lights, renderOptions);
  std::vector<LightToVerify> selected;
  std::string names;
  for (const Light& light : frame.lights) {
    names += (names.empty() ? "\"" : ", \"") + light.name + "\"";
    if (lightName.empty() || light.name == lightName)
      selected.push_back({light, effectiveShadowFar(light, scene.scene->bounds)});
  }
  if (selected.empty())
    throw InputError("light " + lightName + ": no such light (the scene's lights: " + names + ")");
  VerifySettings settings;
  settings.grazing = o.grazing;
  settings.edgeTexels = o.edgeTexels;
  settings.sourceSamples = o.sourceSamples;
  ShadowVerification result;
  {
    py::gil_scoped_release release;
    const ShadowReference reference(*scene.scene);
    result = verifyShadows(reference, scene.scene->bounds, selected, *frame.frame.aovs,
                           frame.camera, settings);
  }
  py::dict out;
  out["width"] = result.width;
  out["height"] = result.height;
  out["camera"] = frame.camera.description;
  py::list table;
  bool pass = true;
  for (std::size_t i = 0; i < result.lights.size(); ++i) {
    const LightVerification& v = result.lights[i];
    const Light& light = selected[i].light;
    py::dict entry;
    entry["name"] = v.name;
    entry["type"] = toString(light.type);
    entry["shadowed"] = v.shadowed;
    if (v.shadowed) {
      entry["filter"] = toString(light.shadow.filter);
      entry["resolution"] = light.shadow.resolution;
      entry["radius"] = light.shadow.radius;
      entry["skipped"] = skipped(v.skipped);
      entry["interior"] = counts(v.interior);
      entry["edge"] = counts(v.edge);
      const bool lightPass = !maxError || worstInteriorErrorRate(v) <= *maxError;
      entry["pass"] = lightPass;
      pass = pass && lightPass;
    }
    table.append(entry);
  }
  out["lights"] = table;
  out["pass"] = pass;
  out["warnings"] = frame.warnings;
  return out;
}

}  // namespace omnishadow::python
