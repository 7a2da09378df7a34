#pragma once

#include "renderer/scene/scene.h"

namespace omnishadow {

// Throws InputError "<file>: the scene draws no triangles (...)" when the loaded scene has
// nothing to render (no instance, or none with a whole triangle), and "<file>: the scene's
// bounds are not finite" when no camera could frame it. Every front end refuses such a scene
// with the same message.
void requireTriangles(const Scene& scene);

}  // namespace omnishadow
