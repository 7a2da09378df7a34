#pragma once

#include "renderer/scene/scene.h"

namespace omnishadow {

// Throws InputError "<file>: the scene draws no triangles (N nodes reached)" when the loaded
// scene has nothing to render. Every front end refuses such a scene with the same message.
void requireTriangles(const Scene& scene);

}  // namespace omnishadow
