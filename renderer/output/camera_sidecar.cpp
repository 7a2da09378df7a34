#include "renderer/output/camera_sidecar.h"

#include <cmath>

#include "renderer/view/camera_export.h"

namespace omnishadow {
namespace {

using Json = nlohmann::ordered_json;

// JSON has no spelling for infinity or NaN.
Json jsonNumber(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

Json rows(const glm::dmat4& m) {
  Json out = Json::array();
  for (int r = 0; r < 4; ++r) {
    Json row = Json::array();
    for (int c = 0; c < 4; ++c) row.push_back(jsonNumber(m[c][r]));
    out.push_back(row);
  }
  return out;
}

}  // namespace

Json cameraSidecar(const ViewCamera& camera, const Scene& scene, std::optional<double> time) {
  const CameraExport e = exportCamera(camera);
  const Json none = nullptr;
  Json doc;
  doc["width"] = e.width;
  doc["height"] = e.height;
  doc["type"] = e.orthographic ? "orthographic" : "perspective";
  doc["intrinsics"] = {{"fx", e.orthographic ? none : jsonNumber(e.fx)},
                       {"fy", e.orthographic ? none : jsonNumber(e.fy)},
                       {"cx", jsonNumber(e.cx)},
                       {"cy", jsonNumber(e.cy)},
                       {"vfovDegrees", e.orthographic ? none : jsonNumber(e.verticalFovDegrees)},
                       {"near", jsonNumber(e.znear)},
                       {"far", e.zfar > 0.0 ? jsonNumber(e.zfar) : none}};
  doc["pixelConvention"] =
      "pixel (i, j) covers [i, i+1) x [j, j+1), j counted down from the top row";
  doc["opengl"] = {{"convention", "camera looks down -Z, +Y up, +X right"},
                   {"worldToCamera", rows(e.worldToCameraGl)},
                   {"cameraToWorld", rows(e.cameraToWorldGl)}};
  doc["opencv"] = {{"convention",
                    "camera looks down +Z, +Y down, +X right; u = fx X/Z + cx, "
                    "v = fy Y/Z + cy"},
                   {"worldToCamera", rows(e.worldToCameraCv)},
                   {"cameraToWorld", rows(e.cameraToWorldCv)}};
  doc["projection"] = {{"convention",
                        "OpenGL camera space to clip space, reversed depth: "
                        "z/w is 1 at near, 0 at far (or infinity)"},
                       {"matrix", rows(e.projection)}};
  doc["time"] = time ? jsonNumber(*time) : none;
  if (camera.gltfCamera >= 0 &&
      static_cast<std::size_t>(camera.gltfCamera) < scene.cameras.size()) {
    const Camera& c = scene.cameras[static_cast<std::size_t>(camera.gltfCamera)];
    doc["gltfCamera"] = {{"index", c.index}, {"name", c.name}, {"node", c.nodeName}};
  } else {
    doc["gltfCamera"] = none;
  }
  doc["description"] = camera.description;
  return doc;
}

}  // namespace omnishadow
