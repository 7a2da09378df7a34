#pragma once

#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

namespace omnishadow {

// A draw of a blended surface: its index among the scene's draws and the world-space centre of
// its bounding sphere.
struct BlendedDraw {
  std::size_t draw = 0;
  glm::vec3 center{0.0f};
};

// The order in which "over" composes blended surfaces right: farthest first along the view
// axis of `view` (a world-to-view matrix), by each draw's centre. Per object, as three.js and
// Filament sort: surfaces that interpenetrate, and one mesh's own overlapping triangles, still
// compose in their stored order. Equal depths keep the order of `draws` (the scene's), so the
// picture is the same run to run. Returns the draws' indices.
std::vector<std::size_t> farthestFirst(const std::vector<BlendedDraw>& draws,
                                       const glm::mat4& view);

}  // namespace omnishadow
