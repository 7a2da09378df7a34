#pragma once

#include <string>

#include "renderer/scene/scene.h"

namespace omnishadow {

// The field of view a perspective camera (glTF yfov, --fov) may have, in degrees: at least
// 0.001 (narrower, automatic framing puts the eye so far away that the scene is lost to float
// precision), less than 180 (from 180 on the projection turns the picture inside out; glTF
// says yfov SHOULD be less than pi).
inline constexpr float kMinFovDegrees = 0.001f;
inline constexpr float kMaxFovDegrees = 180.0f;

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
