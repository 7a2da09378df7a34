#include "renderer/scene/drawable_check.h"

#include <string>

#include "renderer/core/errors.h"

namespace omnishadow {

void requireTriangles(const Scene& scene) {
  if (scene.instances.empty())
    throw InputError(scene.path + ": the scene draws no triangles (" +
                     std::to_string(scene.source.reachedNodes) + " nodes reached)");
}

}  // namespace omnishadow
