// The `omnishadow` Python module: the GL-free render interface (renderer/render/renderer.h) and
// the scene and lights loaders, with NumPy outputs. Errors are the CLI's: InputError (a
// ValueError) carries the one-line message the CLI prints before exiting with status 2,
// RenderError (a RuntimeError) any other failure.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstring>
#include <glm/glm.hpp>

#include "cli/malloc_heap.h"
#include "cli/shader_cache_folder.h"
#include "python/src/py_frame.h"
#include "python/src/py_inputs.h"
#include "python/src/py_renderer.h"
#include "renderer/core/errors.h"
#include "renderer/output/image_writer.h"

namespace py = pybind11;
using namespace omnishadow;
using namespace omnishadow::python;

namespace {

std::string fsPath(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path));
}

py::tuple readImageArray(const py::object& path) {
  const FloatImage image = readImage(fsPath(path));
  py::array_t<float> pixels(
      {py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(image.channels.size())});
  std::memcpy(pixels.mutable_data(), image.pixels.data(), image.pixels.size() * sizeof(float));
  return py::make_tuple(pixels, image.channels);
}

void bindFrame(py::module_& m) {
  py::class_<PyFrame>(m, "Frame",
                      "One rendered frame. Every array is a fresh copy that owns its memory; rows "
                      "are top first, like the images.")
      .def_property_readonly("beauty", &PyFrame::beauty,
                             "H x W x 4 float32: linear, premultiplied RGBA (A = coverage), "
                             "before exposure.")
      .def("to_srgb8", &PyFrame::toSrgb8, py::arg("exposure") = py::none(),
           "H x W x 3 uint8 sRGB, the PNG writer's transform (exposure in stops, default the "
           "render's).")
      .def_property_readonly("channels", &PyFrame::channels,
                             "AOV channel names, as in the CLI's --aov file (empty without AOVs).")
      .def("__getitem__", &PyFrame::channel, py::arg("name"),
           "An AOV channel by its CLI name (H x W float32), e.g. frame['visibility.lamp'], or a "
           "group by its prefix (H x W x n): 'P', 'N', 'albedo', 'diffuse.lamp', "
           "'visibility'. KeyError when absent.")
      .def("__contains__", &PyFrame::contains, py::arg("name"))
      .def("keys", &PyFrame::channels, "Same as channels.")
      .def_property_readonly("depth", &PyFrame::depth,
                             "H x W float32: the Z AOV, distance from the camera in world units "
                             "(0 where nothing was drawn). Needs aovs=[...].")
      .def_property_readonly(
          "object_id", [](const PyFrame& f) { return f.ids("objectId"); },
          "H x W int32: index into the scene's mesh instances, -1 = background. Needs "
          "aovs=['objectId'].")
      .def_property_readonly(
          "material_id", [](const PyFrame& f) { return f.ids("materialId"); },
          "H x W int32: index into the scene's materials (the last is the default material), "
          "-1 = background. Needs aovs=['materialId'].")
      .def_property_readonly("ids", &PyFrame::idIndex,
                             "What object_id and material_id values stand for (the CLI's "
                             "<aov>.ids.json).")
      .def_property_readonly("camera", &PyFrame::cameraDict,
                             "The camera as the CLI's --camera-json sidecar, key for key: "
                             "width, height, type, intrinsics (fx fy cx cy vfovDegrees near "
                             "far), opengl and opencv worldToCamera/cameraToWorld (4 rows of "
                             "4), projection, time, gltfCamera, description.")
      .def_property_readonly("times", &PyFrame::timesDict,
                             "Milliseconds per stage: load, shaders, upload, shadow maps, "
                             "lighting, readback, ...")
      .def_property_readonly("gpu_waits", &PyFrame::gpuWaitsDict,
                             "Milliseconds of the GL stages (upload, shadow maps, lighting) "
                             "spent waiting for the GPU to finish their work: part of times, "
                             "most of a stage bound by the GPU, little of one bound by the CPU")
      .def_property_readonly("shadow_maps", &PyFrame::shadowMaps,
                             "With shadow_maps=True, per shadowed light: point {'type': "
                             "'point', 'distances': 6 x R x R float32 (distance to the light, "
                             "+inf where empty; faces px nx py ny pz nz), 'far', 'faces': "
                             "names}; spot {'type': 'spot', 'distances': R x R (along the map's "
                             "view axis from the light), 'far'}; directional {'type': "
                             "'directional', 'cascades': [{'distances': R x R (along the light "
                             "from the cascade's near plane), 'far'}, ...]}. GL texel rows "
                             "(row 0 = t 0), the values --dump-depth writes.")
      .def_property_readonly(
          "masks", &PyFrame::masks,
          "With masks=True: {'instances': H x W uint16 (mesh instance + 1, 0 = background), "
          "'semantic': H x W uint16 (class id, 0 = background), 'index': the --masks JSON "
          "(per instance: node, mesh, material, class, pixels, bbox [xmin, ymin, xmax, ymax) "
          "and visibleFraction)}.")
      .def(
          "save_masks", [](const PyFrame& f, const py::object& stem) { f.saveMasks(fsPath(stem)); },
          py::arg("stem"),
          "Writes <stem>.instances.png, <stem>.semantic.png (16-bit) and <stem>.masks.json "
          "like --masks.")
      .def_readonly("warnings", &PyFrame::warnings,
                    "The scene's, the lights' and the renderer's warnings, as the CLI prints "
                    "them.")
      .def_readonly("exposure", &PyFrame::exposure)
      .def_property_readonly("width", [](const PyFrame& f) { return f.camera.width; })
      .def_property_readonly("height", [](const PyFrame& f) { return f.camera.height; })
      .def(
          "save", [](const PyFrame& f, const py::object& path) { f.save(fsPath(path)); },
          py::arg("path"),
          "Writes the beauty with the CLI's writers: .png (8-bit sRGB) or .exr (linear half "
          "RGBA), with the render's exposure, all or nothing.")
      .def(
          "save_aovs", [](const PyFrame& f, const py::object& path) { f.saveAovs(fsPath(path)); },
          py::arg("path"), "Writes every AOV channel as float32 OpenEXR, like --aov.");
}

void bindRenderer(py::module_& m) {
  py::class_<PyRenderer> renderer(
      m, "Renderer",
      "A headless GL context and its compiled passes. Reuse one for many "
      "renders (like `omnishadow batch`). It belongs to the thread that made "
      "it: a call from another thread raises RenderError.");
  renderer
      .def(py::init<const py::object&, bool>(), py::arg("gpu") = py::none(),
           py::arg("verbose") = false,
           "gpu: EGL device index (None = the first hardware device, else software). Raises "
           "RenderError when no context can be made, InputError for a gpu that does not exist.")
      .def_property_readonly("platform", &PyRenderer::platform)
      .def_property_readonly("gl", &PyRenderer::gl)
      .def(
          "render",
          [](PyRenderer& r, const PyScene& scene, const py::object& lights,
             const py::object& camera, const py::object& width, const py::object& height,
             const py::object& aovs, const std::string& shading, float exposure, int aa,
             bool shadowMaps, bool masks, bool beauty, bool noGltfLights, double maxMemory,
             const std::string& shadowPass, const std::string& depthPrepass,
             const std::string& finishEachStage) {
            PyRenderOptions o;
            o.camera = camera;
            o.width = width;
            o.height = height;
            o.aovs = aovs;
            o.shading = shading;
            o.exposure = exposure;
            o.shadowMaps = shadowMaps;
            o.masks = masks;
            o.beauty = beauty;
            o.antialiasing = aa;
            o.noGltfLights = noGltfLights;
            o.maxMemoryMiB = maxMemory;
            o.shadowPass = shadowPass;
            o.depthPrepass = depthPrepass;
            o.finishEachStage = finishEachStage;
            return r.render(scene, lights, o);
          },
          py::arg("scene"), py::arg("lights") = py::none(), py::kw_only(),
          py::arg("camera") = py::none(), py::arg("width") = py::none(),
          py::arg("height") = py::none(), py::arg("aovs") = py::none(), py::arg("shading") = "pbr",
          py::arg("exposure") = 0.0f, py::arg("aa") = 1, py::arg("shadow_maps") = false,
          py::arg("masks") = false, py::arg("beauty") = true, py::arg("no_gltf_lights") = false,
          py::arg("max_memory") = 4096.0, py::arg("shadow_pass") = "auto",
          py::arg("depth_prepass") = "auto", py::arg("finish_each_stage") = "auto",
          "Renders `scene` (from load_scene) with the glTF's lights and `lights` (a Lights, a "
          "lights file path, a dict like the file or a list of light dicts; None = the glTF's "
          "only, a headlight when there is none). camera: None, a glTF camera name or index, "
          "or a dict with select/eye/target/up/fov. aovs: None, or a list of --aov-layers "
          "names ([] = the fixed channels). masks: compute annotation masks (Frame.masks). "
          "beauty=False with masks=True alone: masks without a picture, like batch --no-png "
          "--masks (no shadow maps, no lighting; Frame.beauty, to_srgb8 and save raise "
          "ValueError); with anything else the picture is drawn anyway. aa: "
          "beauty samples per pixel (1, 4, 8 or 16; "
          "AOVs, ids, masks and depth stay exact). shadow_pass, depth_prepass and "
          "finish_each_stage: as --shadow-pass, --depth-prepass and --finish-each-stage (the same "
          "picture, another speed; finish_each_stage also decides which stages gpu_waits "
          "has). The GIL is released while it "
          "renders.");
  renderer.def(
      "verify",
      [](PyRenderer& r, const PyScene& scene, const py::object& lights, const std::string& light,
         const py::object& camera, const py::object& width, const py::object& height,
         const std::string& shading, float grazing, float edgeTexels, int sourceSamples,
         const py::object& maxError, bool noGltfLights, double maxMemory,
         const std::string& shadowPass) {
        PyRenderOptions o;
        o.camera = camera;
        o.width = width;
        o.height = height;
        o.shading = shading;
        o.noGltfLights = noGltfLights;
        o.maxMemoryMiB = maxMemory;
        o.shadowPass = shadowPass;
        PyVerifyOptions v;
        v.grazing = grazing;
        v.edgeTexels = edgeTexels;
        v.sourceSamples = sourceSamples;
        v.maxError = maxError;
        return r.verify(scene, lights, o, light, v);
      },
      py::arg("scene"), py::arg("lights") = py::none(), py::kw_only(), py::arg("light") = "",
      py::arg("camera") = py::none(), py::arg("width") = py::none(), py::arg("height") = py::none(),
      py::arg("shading") = "pbr", py::arg("grazing") = 0.05f, py::arg("edge_texels") = 3.0f,
      py::arg("source_samples") = 64, py::arg("max_error") = py::none(),
      py::arg("no_gltf_lights") = false, py::arg("max_memory") = 4096.0,
      py::arg("shadow_pass") = "auto",
      "Renders like render() and checks each light's shadows (or only `light`) against exact "
      "shadow rays, like `omnishadow verify --json`: {'width', 'height', 'camera', 'lights': "
      "[{name, type, shadowed, filter, resolution, radius, skipped, interior, edge, pass}], "
      "'pass', 'warnings'}; interior and edge hold evaluated, agree, falseShadow, falseLight and "
      "their rates. max_error (a fraction) bounds the interior error rates for 'pass'.");
}

}  // namespace

PYBIND11_MODULE(omnishadow, m) {
  m.doc() =
      "omnishadow: headless glTF renderer with shadowed point, spot and directional lights, "
      "with NumPy outputs. See the README, section 'Python'.";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError).doc() =
      "Bad input (a file, a field, an argument): the CLI's one-line message.";
  py::register_exception<RenderError>(m, "RenderError", PyExc_RuntimeError).doc() =
      "Any other failure: no GL context, a GL error, a file that cannot be written.";

  py::class_<PyScene>(m, "Scene", "A loaded glTF scene (read only); render it many times.")
      .def_property_readonly("path", [](const PyScene& s) { return s.scene->path; })
      .def_property_readonly("instance_count",
                             [](const PyScene& s) { return s.scene->instances.size(); })
      .def_property_readonly(
          "light_names",
          [](const PyScene& s) {
            std::vector<std::string> names;
            for (const Light& light : s.scene->lights) names.push_back(light.name);
            return names;
          },
          "The glTF's KHR_lights_punctual lights.")
      .def_property_readonly("camera_names",
                             [](const PyScene& s) {
                               std::vector<std::string> names;
                               for (const Camera& camera : s.scene->cameras)
                                 names.push_back(camera.name);
                               return names;
                             })
      .def_property_readonly(
          "material_variants", [](const PyScene& s) { return s.scene->source.materialVariants; },
          "The file's KHR_materials_variants names (load_scene's variant chooses one).")
      .def_property_readonly(
          "material_variant",
          [](const PyScene& s) -> py::object {
            const SourceSummary& source = s.scene->source;
            if (source.materialVariant < 0) return py::none();
            return py::str(
                source.materialVariants[static_cast<std::size_t>(source.materialVariant)]);
          },
          "The variant drawn, or None for the default materials.")
      .def_property_readonly("warnings", [](const PyScene& s) { return s.scene->warnings; })
      .def("posed", &posedScene, py::arg("time"), py::arg("animation") = py::none(),
           "This scene posed anew at `time` (seconds; None = the rest pose) with the clips "
           "`animation` names (as load_scene's), without reading the file again: what "
           "load_scene(path, time=time, animation=animation) with this scene's other options "
           "gives, with the same messages and warnings. For the frames of an animation "
           "(CesiumMilkTruck: 57 ms to load, 0.02 to pose, since the posed scene shares its "
           "source's pixels, and its render 5 ms shorter).");

  py::class_<PyLights>(m, "Lights", "A lights file's content, validated.")
      .def_property_readonly("names",
                             [](const PyLights& l) {
                               std::vector<std::string> names;
                               for (const Light& light : l.setup.lights)
                                 names.push_back(light.name);
                               return names;
                             })
      .def_property_readonly("ambient",
                             [](const PyLights& l) {
                               return py::make_tuple(l.setup.ambient.x, l.setup.ambient.y,
                                                     l.setup.ambient.z);
                             })
      .def_property_readonly(
          "environment",
          [](const PyLights& l) -> py::object {
            if (!l.setup.environment) return py::none();
            const EnvironmentLight& e = *l.setup.environment;
            py::dict environment;
            environment["image"] =
                e.image.empty() ? py::object(py::none()) : py::object(py::str(e.image.string()));
            environment["color"] = py::make_tuple(e.color.x, e.color.y, e.color.z);
            environment["intensity"] = e.intensity;
            environment["rotation"] = glm::degrees(e.rotation);  // as the file writes it
            environment["background"] = e.background;
            environment["sun"] = e.sun;
            return environment;
          },
          "The environment light as a dict (image path resolved, rotation in degrees), or None.")
      .def_property_readonly(
          "ambient_occlusion",
          [](const PyLights& l) -> py::object {
            if (!l.setup.ambientOcclusion) return py::none();
            const AmbientOcclusion& o = *l.setup.ambientOcclusion;
            py::dict occlusion;
            occlusion["radius"] =
                o.radius > 0.0f ? py::object(py::float_(o.radius)) : py::object(py::none());
            occlusion["strength"] = o.strength;
            return occlusion;
          },
          "The screen-space ambient occlusion as a dict (radius None: 5% of each scene's "
          "diagonal), or None.")
      .def_readonly("warnings", &PyLights::warnings);

  m.def(
      "load_scene",
      [](const py::object& path, const py::object& scene, const py::object& time,
         const py::object& animation, const py::object& variant, bool allowExternalUris) {
        return loadScene(fsPath(path), scene, time, animation, variant, allowExternalUris);
      },
      py::arg("path"), py::arg("scene") = py::none(), py::kw_only(), py::arg("time") = py::none(),
      py::arg("animation") = py::none(), py::arg("variant") = py::none(),
      py::arg("allow_external_uris") = false,
      "Loads a .gltf or .glb like the CLI (scene: index of the glTF scene, None = the file's "
      "default), posed like the CLI's --time and --animation: time in seconds (None = the rest "
      "pose), animation = a clip name, index or 'all' (None = all; needs time); variant = a "
      "KHR_materials_variants name or index, like --variant (None = the default materials). "
      "Raises InputError with the CLI's message for unreadable or invalid files.");
  m.def("load_lights", &loadLights, py::arg("source"), py::arg("label") = "lights",
        "A lights file path, a dict with the lights file's schema or a list of light dicts, "
        "validated with the lights file's messages (`label` stands for the file name in them).");
  m.def("read_image", &readImageArray, py::arg("path"),
        "Reads a PNG or EXR as float32 (H x W x C, rows top first; PNG values in [0, 1]) and "
        "its channel names, with the reader the CLI's diff uses.");

  m.def(
      "use_rendering_heap",
      [] {
        const cli::MallocHeapSetUp setUp = cli::setUpMallocHeap();
        py::dict result;
        result["applied"] = setUp.applied;
        result["page_fault_us"] = setUp.heapTop.pageFaultMicroseconds;
        result["huge_pages"] = setUp.heapTop.hugePages;
        return result;
      },
      "Sets this process's malloc up as `omnishadow batch` has it: every block from one heap "
      "(none mapped on its own), one arena for all threads, nothing given back to the system "
      "below 1 GiB, and where a fresh 4 KiB page is dear (5 us or more, measured here) the "
      "heap's top in transparent huge pages. Each render then reuses the memory the renders "
      "before it freed instead of faulting in fresh pages (on a 2-core VM, 40 scenes at "
      "1280x720 in a loop: 1.57 s with it, 2.45 s without). "
      "Process-wide and for good, so the process's choice: call it once, early, in a "
      "process that mostly renders. Later calls change nothing. Returns {'applied': False "
      "under valgrind or AddressSanitizer, or with OMNISHADOW_MEMORY_WARMUP=0; "
      "'page_fault_us': what a fresh page cost; 'huge_pages': whether the top asks for them}.");

  m.def(
      "keep_shader_cache",
      [] {
        // Once per process: after the first call the variable is set, which a second look
        // would take for the user's own choice. (Plain data: a static Python object would
        // outlive the interpreter.)
        static const cli::ShaderCacheFolder choice = cli::keepShaderCacheUsable();
        using Source = cli::ShaderCacheFolder::Source;
        constexpr auto name = [](Source source) {
          switch (source) {
            case Source::MesasOwn:
              return "mesa";
            case Source::OwnFallback:
              return "fallback";
            case Source::None:
              return "none";
            case Source::UsersChoice:
              break;
          }
          return "users_choice";
        };
        py::dict result;
        result["source"] = name(choice.source);
        result["folder"] = choice.shadersFolder().string();
        result["description"] = cli::describeShaderCacheFolder(choice);
        return result;
      },
      "Keeps Mesa's shader cache usable as the CLI does: where Mesa's own place for it "
      "($XDG_CACHE_HOME, else ~/.cache of the user's home in the password database) cannot be "
      "written, as for a container's user without a home, sets MESA_SHADER_CACHE_DIR to "
      "$TMPDIR/omnishadow-shader-cache-<uid> (or under /tmp), a folder only this user may "
      "enter, so that later processes load the shaders this one compiles (50-120 ms each) "
      "instead of compiling them again. Mesa reads the variable when the first Renderer opens "
      "the display, and setting one is not safe while another thread reads the environment: "
      "call it first, before any Renderer and any thread. Leaves Mesa's own variables "
      "(MESA_SHADER_CACHE_DIR, MESA_SHADER_CACHE_DISABLE, their MESA_GLSL_ names) alone. Once "
      "per process; returns {'source': 'users_choice', 'mesa', 'fallback' or 'none', 'folder': "
      "where the shaders go ('' for users_choice and none), 'description': one line}.");

  bindRenderer(m);
  bindFrame(m);
}
