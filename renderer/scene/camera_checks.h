#pragma once

#include <string>

#include "renderer/scene/scene.h"

namespace omnishadow {

// Why no image can be rendered from `camera`, or empty when one can: its projection would
// divide by zero or hold infinities or NaNs (glTF 2.0 requires orthographic xmag and ymag to be
// non-zero, zfar to be greater than znear, and perspective yfov and znear to be positive).
// E.g. "orthographic ymag must be non-zero".
//
// A file with such a camera still loads (the loader warns): other glTF viewers load it too, and
// a broken camera that is never used must not keep the rest of the scene from rendering. Only
// rendering from that camera is refused (resolveCamera() calls checkCameraUsable()).
std::string cameraProblem(const Camera& camera);

// Throws InputError "<scene.path>: cameras[<camera.index>]: <problem>" for such a camera.
void checkCameraUsable(const Scene& scene, const Camera& camera);

}  // namespace omnishadow
