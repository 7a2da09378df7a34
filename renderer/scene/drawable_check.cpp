#include "renderer/scene/drawable_check.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "renderer/core/errors.h"

namespace omnishadow {

void requireTriangles(const Scene& scene) {
  if (scene.instances.empty())
    throw InputError(scene.path + ": the scene draws no triangles (" +
                     std::to_string(scene.source.reachedNodes) + " nodes reached" +
                     (scene.source.hiddenNodes > 0
                          ? ", " + std::to_string(scene.source.hiddenNodes) +
                                " of them hidden by KHR_node_visibility"
                          : std::string()) +
                     ")");
  // Primitives with fewer than 3 vertices (or only degenerate strips) leave instances that
  // draw nothing: a black picture is no answer.
  if (std::none_of(scene.instances.begin(), scene.instances.end(),
                   [&](const MeshInstance& instance) {
                     return !scene.meshes[static_cast<std::size_t>(instance.mesh)].indices.empty();
                   }))
    throw InputError(scene.path + ": the scene draws no triangles (" +
                     std::to_string(scene.instances.size()) +
                     " primitives placed, none with a whole triangle)");
  // Instances at +-3e38 make the bounds infinite: no camera or shadow range can frame them.
  if (!std::isfinite(scene.bounds.radius()) || !std::isfinite(glm::length(scene.bounds.center())))
    throw InputError(scene.path +
                     ": the scene's bounds are not finite (objects placed near the float limit)");
}

}  // namespace omnishadow
