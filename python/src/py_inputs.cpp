#include "python/src/py_inputs.h"

#include <pybind11/stl.h>

#include <cmath>

#include "renderer/core/errors.h"
#include "renderer/scene/drawable_check.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_loader.h"
#include "renderer/scene/scene_pose.h"

namespace py = pybind11;

namespace omnishadow::python {
namespace {

bool isPath(const py::object& value) {
  return py::isinstance<py::str>(value) ||
         py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

std::string pathString(const py::object& value) {
  return py::str(py::module_::import("os").attr("fspath")(value));
}

// Python data as the text of a lights file. NaN and infinity have no JSON spelling; NumPy
// numbers and arrays become plain lists.
std::string lightsJson(const py::object& data, const std::string& label) {
  const py::object json = py::module_::import("json");
  const py::cpp_function plain([](const py::object& value) -> py::object {
    if (py::hasattr(value, "tolist")) return value.attr("tolist")();
    throw py::type_error("not JSON data: " + std::string(py::str(py::type::of(value))));
  });
  try {
    return py::str(
        json.attr("dumps")(data, py::arg("allow_nan") = false, py::arg("default") = plain));
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_ValueError) && !e.matches(PyExc_TypeError)) throw;
    throw InputError(label + ": " + std::string(py::str(e.value())));
  }
}

std::optional<glm::vec3> vec3Field(const py::dict& camera, const char* key) {
  if (!camera.contains(key) || camera[key].is_none()) return std::nullopt;
  std::vector<float> v;
  try {
    v = camera[key].cast<std::vector<float>>();
  } catch (const py::cast_error&) {
  }
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw InputError(std::string("camera[\"") + key +
                     "\"]: expected 3 finite numbers, e.g. (0, 1.5, 4)");
  return glm::vec3(v[0], v[1], v[2]);
}

std::optional<int> size(const py::object& value, const char* name) {
  if (value.is_none()) return std::nullopt;
  const long long n = value.cast<long long>();
  if (n < 1 || n > 16384)
    throw InputError(std::string(name) + " " + std::to_string(n) +
                     ": expected a size from 1 to 16384");
  return static_cast<int>(n);
}

// A selection the CLI takes as text, a name or an index: a str as it is, an int (not a bool)
// in decimal, None as empty; anything else raises TypeError with `message`.
std::string nameOrIndex(const py::object& value, const char* message) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value))
    return std::to_string(value.cast<long long>());
  if (!value.is_none()) throw py::type_error(message);
  return {};
}

// A pose's time: a real number of seconds, or None for the rest pose.
std::optional<double> secondsOf(const py::object& time) {
  if (time.is_none()) return std::nullopt;
  if (py::isinstance<py::bool_>(time) ||
      !py::isinstance(time, py::module_::import("numbers").attr("Real")))
    throw py::type_error("time: expected a number of seconds or None");
  return time.cast<double>();
}

// The CLI's --animation text: a name, an index or "all" (empty: all).
std::string clipsOf(const py::object& animation) {
  return nameOrIndex(animation, "animation: expected a name, an index, \"all\" or None");
}

}  // namespace

PyScene loadScene(const std::string& path, const py::object& sceneIndex, const py::object& time,
                  const py::object& animation, const py::object& variant, bool allowExternalUris) {
  const std::optional<double> seconds = secondsOf(time);
  const std::string clips = clipsOf(animation);
  GltfLoadOptions options;
  options.allowExternalUris = allowExternalUris;
  options.materialVariant = nameOrIndex(variant, "variant: expected a name, an index or None");
  if (!sceneIndex.is_none()) {
    const long long index = sceneIndex.cast<long long>();
    if (index < 0 || index > 1'000'000'000)
      throw InputError(path + ": scene " + std::to_string(index) + ": expected an index >= 0");
    options.sceneIndex = static_cast<int>(index);
  }
  py::gil_scoped_release release;  // loading is CPU only and may take long
  auto scene = std::make_shared<Scene>(loadGltf(path, options));
  requireTriangles(*scene);
  // Posed like the CLI's render (loadJob): the pose's warnings follow the loader's. The loader
  // left the scene at rest, so without a time there is nothing to pose.
  const std::size_t loaderWarnings = scene->warnings.size();
  if (!seconds) {
    checkPoseRequest(seconds, clips);
    return PyScene{std::move(scene), seconds, loaderWarnings};
  }
  const std::vector<std::string> warnings = poseSceneChecked(*scene, path, seconds, clips);
  scene->warnings.insert(scene->warnings.end(), warnings.begin(), warnings.end());
  return PyScene{std::move(scene), seconds, loaderWarnings};
}

PyScene posedScene(const PyScene& scene, const py::object& time, const py::object& animation) {
  const std::optional<double> seconds = secondsOf(time);
  const std::string clips = clipsOf(animation);
  if (!seconds && !scene.time) {  // at rest already: the same scene
    checkPoseRequest(seconds, clips);
    return scene;
  }
  py::gil_scoped_release release;  // a copy (its pixels shared), and skinning
  auto posed = std::make_shared<Scene>(*scene.scene);
  posed->warnings.resize(scene.loaderWarnings);
  const std::vector<std::string> warnings = poseSceneChecked(*posed, posed->path, seconds, clips);
  posed->warnings.insert(posed->warnings.end(), warnings.begin(), warnings.end());
  return PyScene{std::move(posed), seconds, scene.loaderWarnings};
}

PyLights loadLights(const py::object& source, const std::string& label) {
  PyLights lights;
  if (isPath(source)) {
    lights.label = pathString(source);
    lights.setup = loadLightsFile(lights.label, lights.warnings);
    return lights;
  }
  py::object data = source;
  if (py::isinstance<py::list>(source) || py::isinstance<py::tuple>(source)) {
    py::dict file;
    file["lights"] = source;
    data = file;
  } else if (!py::isinstance<py::dict>(source)) {
    throw InputError(label + ": expected a lights file path, a dict like the lights file or a " +
                     "list of light dicts");
  }
  lights.label = label;
  lights.setup = parseLights(lightsJson(data, label), label, lights.warnings);
  return lights;
}

CameraRequest cameraRequest(const py::object& camera, const py::object& width,
                            const py::object& height) {
  CameraRequest request;
  request.width = size(width, "width");
  request.height = size(height, "height");
  if (camera.is_none()) return request;
  if (py::isinstance<py::str>(camera)) {
    request.select = camera.cast<std::string>();
  } else if (py::isinstance<py::int_>(camera)) {
    request.select = std::to_string(camera.cast<long long>());
  } else if (py::isinstance<py::dict>(camera)) {
    const py::dict d = camera;
    for (const auto& [key, value] : d) {
      const std::string name = py::str(key);
      if (name != "select" && name != "eye" && name != "target" && name != "up" && name != "fov")
        throw InputError("camera[\"" + name +
                         "\"]: unknown key (expected select, eye, target, up or fov)");
    }
    if (d.contains("select") && !d["select"].is_none())
      request.select = std::string(py::str(d["select"]));
    request.eye = vec3Field(d, "eye");
    request.target = vec3Field(d, "target");
    request.up = vec3Field(d, "up");
    if (d.contains("fov") && !d["fov"].is_none()) request.fovDegrees = d["fov"].cast<float>();
  } else {
    throw InputError("camera: expected None, a glTF camera name or index, or a dict");
  }
  return request;
}

}  // namespace omnishadow::python
