#include "python/src/py_frame.h"

#include <pybind11/stl.h>

#include <cmath>
#include <cstring>

#include "renderer/core/errors.h"
#include "renderer/output/annotation_masks.h"
#include "renderer/output/camera_sidecar.h"
#include "renderer/output/depth_dump.h"
#include "renderer/output/display_transform.h"
#include "renderer/output/exr_camera.h"
#include "renderer/output/id_index.h"
#include "renderer/output/output_transaction.h"

namespace py = pybind11;

namespace omnishadow::python {
namespace {

// A fresh (owning) H x W x n array with `channels` of `image`, in that order; H x W when
// `squeeze` and n = 1.
template <typename T>
py::array_t<T> copyChannels(const FloatImage& image, const std::vector<int>& channels,
                            bool squeeze) {
  const py::ssize_t h = image.height, w = image.width, n = py::ssize_t(channels.size());
  py::array_t<T> out = squeeze && n == 1 ? py::array_t<T>({h, w}) : py::array_t<T>({h, w, n});
  T* dst = out.mutable_data();
  const std::size_t stride = image.channels.size();
  const std::size_t pixels = std::size_t(h) * std::size_t(w);
  for (std::size_t i = 0; i < pixels; ++i)
    for (std::size_t c = 0; c < channels.size(); ++c)
      dst[i * channels.size() + c] = static_cast<T>(image.pixels[i * stride + channels[c]]);
  return out;
}

py::object jsonToPython(const nlohmann::ordered_json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

}  // namespace

const FloatImage& PyFrame::picture(const char* what) const {
  if (frame.beauty.pixels.empty())
    throw py::value_error(std::string(what) +
                          ": this frame has no picture; it was rendered with beauty=False "
                          "(masks alone)");
  return frame.beauty;
}

py::array_t<float> PyFrame::beauty() const {
  return copyChannels<float>(picture("Frame.beauty"), {0, 1, 2, 3}, false);
}

py::array_t<std::uint8_t> PyFrame::toSrgb8(const py::object& exposureStops) const {
  const float stops = exposureStops.is_none() ? exposure : exposureStops.cast<float>();
  if (!std::isfinite(stops))
    throw InputError("exposure " + std::to_string(stops) + ": expected a finite number of stops");
  const std::vector<std::uint8_t> srgb = omnishadow::toSrgb8(picture("Frame.to_srgb8"), stops);
  py::array_t<std::uint8_t> out(
      {py::ssize_t(frame.beauty.height), py::ssize_t(frame.beauty.width), py::ssize_t(3)});
  std::memcpy(out.mutable_data(), srgb.data(), srgb.size());
  return out;
}

std::vector<std::string> PyFrame::channels() const {
  return frame.aovs ? frame.aovs->channels : std::vector<std::string>{};
}

const FloatImage& PyFrame::aovs(const std::string& wanted) const {
  if (!frame.aovs)
    throw py::key_error(wanted +
                        ": this frame has no AOVs; render with aovs=[] (the fixed "
                        "channels) or aovs=[\"objectId\", ...] (with layers)");
  return *frame.aovs;
}

const FloatImage& PyFrame::objectIds() const {
  if (!frame.objectIds) aovs("masks");  // without AOVs either: a KeyError that says how to ask
  return objectIdImage(frame);
}

bool PyFrame::contains(const std::string& name) const {
  if (!frame.aovs) return false;
  for (const std::string& channel : frame.aovs->channels)
    if (channel == name || channel.rfind(name + ".", 0) == 0) return true;
  return false;
}

py::array_t<float> PyFrame::channel(const std::string& name) const {
  const FloatImage& image = aovs(name);
  const int exact = image.channelIndex(name);
  if (exact >= 0) return copyChannels<float>(image, {exact}, true);
  std::vector<int> group;
  for (std::size_t c = 0; c < image.channels.size(); ++c)
    if (image.channels[c].rfind(name + ".", 0) == 0) group.push_back(int(c));
  if (group.empty())
    throw py::key_error(name + ": no such AOV channel in this frame (see Frame.channels)");
  return copyChannels<float>(image, group, false);
}

py::array_t<float> PyFrame::depth() const {
  return channel("Z");
}

py::array_t<std::int32_t> PyFrame::ids(const std::string& name) const {
  const FloatImage& image = aovs(name);
  const int c = image.channelIndex(name);
  if (c < 0)
    throw py::key_error(name + ": not rendered; add \"" + name + "\" to the render's aovs");
  return copyChannels<std::int32_t>(image, {c}, true);
}

py::dict PyFrame::cameraDict() const {
  return jsonToPython(cameraSidecar(camera, *scene, time)).cast<py::dict>();
}

py::dict PyFrame::timesDict() const {
  py::dict d;
  for (const auto& [stage, ms] : times.stages()) d[py::str(stage)] = ms;
  return d;
}

py::dict PyFrame::gpuWaitsDict() const {
  py::dict d;
  for (const auto& [stage, ms] : times.waits()) d[py::str(stage)] = ms;
  return d;
}

py::dict PyFrame::shadowMaps() const {
  py::dict maps;
  for (const ShadowMapDump& dump : frame.shadowMaps) {
    const py::ssize_t r = dump.distances.resolution;
    py::array_t<float> faces({py::ssize_t(kCubeFaceCount), r, r});
    for (int f = 0; f < kCubeFaceCount; ++f)
      std::memcpy(faces.mutable_data(f), dump.distances.faces[f].data(),
                  dump.distances.faces[f].size() * sizeof(float));
    py::dict entry;
    entry["distances"] = faces;
    entry["far"] = dump.far;
    entry["faces"] = py::make_tuple("px", "nx", "py", "ny", "pz", "nz");
    entry["type"] = "point";
    maps[py::str(dump.light)] = entry;
  }
  // Spot maps and cascades come light by light, cascades in order (frame.h).
  for (const PlanarShadowMapDump& dump : frame.planarShadowMaps) {
    const py::ssize_t r = dump.resolution;
    py::array_t<float> texels({r, r});
    std::memcpy(texels.mutable_data(), dump.distances.data(),
                dump.distances.size() * sizeof(float));
    py::dict map;
    map["distances"] = texels;
    map["far"] = dump.far;
    if (dump.planar == "spot") {
      map["type"] = "spot";
      maps[py::str(dump.light)] = map;
      continue;
    }
    const py::str light(dump.light);
    if (!maps.contains(light)) {
      py::dict entry;
      entry["type"] = "directional";
      entry["cascades"] = py::list();
      maps[light] = entry;
    }
    py::list(py::dict(maps[light])["cascades"]).append(map);
  }
  return maps;
}

py::dict PyFrame::idIndex() const {
  return jsonToPython(omnishadow::idIndex(*scene));
}

const AnnotationMasks& PyFrame::annotationMasks() const {
  if (!masks_) masks_ = omnishadow::annotationMasks(*scene, camera, objectIds());
  return *masks_;
}

py::dict PyFrame::masks() const {
  const AnnotationMasks& made = annotationMasks();
  auto array = [&](const std::vector<std::uint16_t>& values) {
    py::array_t<std::uint16_t> out({py::ssize_t(made.height), py::ssize_t(made.width)});
    std::memcpy(out.mutable_data(), values.data(), values.size() * sizeof(std::uint16_t));
    return out;
  };
  py::dict d;
  d["instances"] = array(made.instances);
  d["semantic"] = array(made.classes);
  d["index"] = jsonToPython(made.index);
  return d;
}

void PyFrame::saveMasks(const std::string& stem) const {
  OutputTransaction transaction;
  writeAnnotationMasks(encodeAnnotationMasks(annotationMasks()), stem, transaction);
  transaction.commit();
}

void PyFrame::save(const std::string& path) const {
  picture("Frame.save");
  const std::string ext = std::filesystem::path(path).extension().string();
  OutputTransaction transaction;
  if (ext == ".png" || ext == ".PNG") {
    writePng(transaction.stage(path), frame.beauty.width, frame.beauty.height, 3,
             omnishadow::toSrgb8(frame.beauty, exposure));
  } else if (ext == ".exr" || ext == ".EXR") {
    const ExrCameraAttributes attributes = exrCameraAttributes(camera);
    writeExr(transaction.stage(path), applyExposure(frame.beauty, exposure), ExrPixelType::Half,
             &attributes);
  } else {
    throw InputError(path + ": unsupported image format (use .png or .exr)");
  }
  transaction.commit();
}

void PyFrame::saveAovs(const std::string& path) const {
  const FloatImage& image = aovs("save_aovs");
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".exr" && ext != ".EXR")
    throw InputError("--aov " + path + ": AOVs are written as OpenEXR; use a .exr name");
  OutputTransaction transaction;
  const ExrCameraAttributes attributes = exrCameraAttributes(camera);
  writeExr(transaction.stage(path), image, ExrPixelType::Float, &attributes);
  transaction.commit();
}

}  // namespace omnishadow::python
