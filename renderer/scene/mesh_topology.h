#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace omnishadow {

// Whether an indexed triangle list is the boundary of a solid with counter-clockwise front
// faces outside (glTF's winding). Seen from any point outside such a mesh, the nearest surface
// along every ray is a front face, so a shadow pass may skip its back faces without changing a
// depth (renderer/shadow_pass.cpp).
//
// True when, after welding bit-identical positions, every edge of a non-degenerate triangle is
// shared by exactly two triangles that run along it in opposite directions (a closed,
// consistently oriented surface), and every connected piece encloses a positive volume. Open
// meshes, inside-out pieces, flat two-sided sheets and meshes without triangles are not closed.
bool isClosedSolid(const std::vector<glm::vec3>& positions,
                   const std::vector<std::uint32_t>& indices);

}  // namespace omnishadow
