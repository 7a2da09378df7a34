#pragma once

#include "renderer/scene/bounds.h"
#include "renderer/scene/light.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// The light a render uses when the scene and the lights file have none, so that it still shows
// something: a point light named "headlight" at the camera, slightly above, giving about 1 lux
// at the scene center. Front ends (the CLI, the Python module) add it the same way.
Light headlight(const ViewCamera& camera, const Bounds& bounds);

// The warning that goes with it.
inline constexpr const char* kHeadlightWarning =
    "no lights in the scene or a lights file: using a headlight at the camera";

}  // namespace omnishadow
