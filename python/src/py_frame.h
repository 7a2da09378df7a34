#pragma once

// A rendered frame as Python sees it: NumPy copies of the renderer's images (each array owns its
// memory, rows top first), the camera, stage times and the writers of the CLI.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/core/stage_timer.h"
#include "renderer/output/annotation_masks.h"
#include "renderer/render/frame.h"
#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"

namespace omnishadow::python {

struct PyFrame {
  Frame frame;
  std::shared_ptr<const Scene> scene;
  ViewCamera camera;
  std::optional<double> time;  // the scene's pose time, for the camera sidecar
  StageTimes times;
  float exposure = 0.0f;
  std::vector<std::string> warnings;  // the scene's, the lights', then the renderer's
  std::vector<Light> lights;          // as rendered: merged, or the headlight

  pybind11::array_t<float> beauty() const;
  pybind11::array_t<std::uint8_t> toSrgb8(const pybind11::object& exposure) const;
  std::vector<std::string> channels() const;
  bool contains(const std::string& name) const;
  // A channel by its CLI name (H x W), or a group of them by their common prefix: "P", "N",
  // "albedo", "diffuse.<light>", "visibility" (H x W x n, in channel order).
  pybind11::array_t<float> channel(const std::string& name) const;
  pybind11::array_t<float> depth() const;
  pybind11::array_t<std::int32_t> ids(const std::string& channel) const;
  // The CLI's --camera-json document (renderer/output/camera_sidecar.h) as Python data.
  pybind11::dict cameraDict() const;
  pybind11::dict timesDict() const;
  pybind11::dict gpuWaitsDict() const;
  pybind11::dict shadowMaps() const;
  // What objectId and materialId stand for, as the CLI's "<aov>.ids.json".
  pybind11::dict idIndex() const;
  // Annotation masks (render(masks=True)): {"instances", "semantic": H x W uint16, "index": the
  // --masks JSON as a dict}.
  pybind11::dict masks() const;
  // The CLI's --masks files: "<stem>.instances.png", "<stem>.semantic.png", "<stem>.masks.json".
  void saveMasks(const std::string& stem) const;
  // The beauty as .png (8-bit sRGB) or .exr (linear half RGBA), after exposure, like -o.
  void save(const std::string& path) const;
  // Every AOV channel as float32 OpenEXR, like --aov.
  void saveAovs(const std::string& path) const;

 private:
  // The beauty; ValueError naming `what` for a frame rendered with beauty=False.
  const FloatImage& picture(const char* what) const;
  const FloatImage& aovs(const std::string& wanted) const;
  // What masks are made from: Frame::objectIds (masks=True), else the AOVs.
  const FloatImage& objectIds() const;
  // Made by the first masks() or saveMasks() (every instance rasterized alone on the CPU: tens
  // of milliseconds on a real scene), kept for the next; Python calls them holding the GIL.
  const AnnotationMasks& annotationMasks() const;
  mutable std::optional<AnnotationMasks> masks_;
};

}  // namespace omnishadow::python
