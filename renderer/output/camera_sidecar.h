#pragma once

#include <nlohmann/json.hpp>
#include <optional>

#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// The camera sidecar (the CLI's --camera-json; Python's frame.camera is the same document):
// image size, intrinsics, world-to-camera and camera-to-world matrices in the OpenGL and OpenCV
// conventions (renderer/view/camera_export.h), the projection, the time and the glTF camera.
// Matrices are written as 4 rows of 4 numbers.
nlohmann::ordered_json cameraSidecar(const ViewCamera& camera, const Scene& scene,
                                     std::optional<double> time);

}  // namespace omnishadow
