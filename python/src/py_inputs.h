#pragma once

// The inputs of a Python render: scenes, lights and camera requests, converted from Python
// values with the CLI's loaders and the CLI's messages.

#include <pybind11/pybind11.h>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/scene/light.h"
#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"

namespace omnishadow::python {

// A loaded scene, shared (read only) by every frame rendered from it.
struct PyScene {
  std::shared_ptr<const Scene> scene;
  std::optional<double> time;      // the pose's time (load_scene(time=)); none = the rest pose
  std::size_t loaderWarnings = 0;  // scene->warnings' first ones are the loader's, then the pose's
};

// A lights file's content: the lights, the ambient term and the loader's warnings.
struct PyLights {
  LightSetup setup;
  std::vector<std::string> warnings;
  std::string label;  // the file, or the label given for Python data
};

// loadGltf() with the CLI's checks (a scene that draws no triangles is refused), posed at `time`
// (seconds or None) with the clips `animation` names (a name, an index, "all" or None = all) as
// the CLI's --time and --animation do, with their messages; `variant` (a name, an index or None)
// chooses a KHR_materials_variants variant as the CLI's --variant does.
PyScene loadScene(const std::string& path, const pybind11::object& sceneIndex,
                  const pybind11::object& time, const pybind11::object& animation,
                  const pybind11::object& variant, bool allowExternalUris);

// `scene` posed anew at `time` (seconds or None = the rest pose) with the clips `animation`
// names, as loadScene() poses a load of its file, with the same messages and warnings; the file
// is not read again. A copy (`scene` itself where both are at rest): the renderer takes its
// images as those it drew (and its meshes too where no mesh is deformed), as for the scene it
// came from.
PyScene posedScene(const PyScene& scene, const pybind11::object& time,
                   const pybind11::object& animation);

// A lights file path (str or os.PathLike), a dict with the lights file's schema, or a list of
// light dicts (the file's "lights" array). Python data goes through the lights file parser, so
// it is validated with the same messages, `label` standing for the file name.
PyLights loadLights(const pybind11::object& source, const std::string& label);

// None, a glTF camera name (str) or index (int), or a dict with any of "select", "eye",
// "target", "up" (3 numbers each) and "fov" (degrees), like --camera, --eye, --target, --up,
// --fov. Image size from width/height (None = the CLI's default).
CameraRequest cameraRequest(const pybind11::object& camera, const pybind11::object& width,
                            const pybind11::object& height);

}  // namespace omnishadow::python
