#pragma once

// omnishadow.Renderer: the GL context and its passes, bound to the thread that made it.

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <thread>

#include "python/src/py_frame.h"
#include "python/src/py_inputs.h"
#include "renderer/render/renderer.h"

namespace omnishadow::python {

// What renderer.render() takes besides the scene and the lights (the CLI's render options).
struct PyRenderOptions {
  pybind11::object camera = pybind11::none();
  pybind11::object width = pybind11::none();
  pybind11::object height = pybind11::none();
  pybind11::object aovs = pybind11::none();  // None: no AOVs; a list: the fixed ones + layers
  std::string shading = "pbr";
  float exposure = 0.0f;
  bool shadowMaps = false;
  int antialiasing = 1;  // aa=: beauty samples per pixel (1, 4, 8, 16)
  bool masks = false;    // adds the objectId layer the masks are made from
  bool beauty = true;    // false: no picture (RenderSettings::beauty)
  bool noGltfLights = false;
  double maxMemoryMiB = 4096.0;
  std::string shadowPass = "auto";
  std::string depthPrepass = "auto";
  std::string finishEachStage = "auto";  // RenderSettings::finishEachStage: auto, on or off
};

// verify()'s options, the CLI's verify options.
struct PyVerifyOptions {
  float grazing = 0.05f;
  float edgeTexels = 3.0f;
  int sourceSamples = 64;
  pybind11::object maxError = pybind11::none();  // fraction; None = no pass/fail bound
};

class PyRenderer {
 public:
  PyRenderer(const pybind11::object& gpu, bool verbose);

  // Loads `lights` when it is not a Lights object yet, renders with the GIL released.
  PyFrame render(const PyScene& scene, const pybind11::object& lights,
                 const PyRenderOptions& options);
  // The shadow agreement table of `omnishadow verify --json` for a render with these options:
  // {"width", "height", "camera", "lights": [{name, type, shadowed, filter, resolution, radius,
  // skipped, interior, edge, pass}], "pass"}.
  pybind11::dict verify(const PyScene& scene, const pybind11::object& lights,
                        const PyRenderOptions& options, const std::string& light,
                        const PyVerifyOptions& verify);
  std::string platform() const;
  std::string gl() const;

 private:
  // A GL context is current on one thread only: any other thread gets a RenderError.
  void checkThread(const char* what) const;

  std::unique_ptr<Renderer> renderer_;
  std::thread::id owner_;
};

}  // namespace omnishadow::python
