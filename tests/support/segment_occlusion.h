#pragma once

// Exact segment-against-triangles tests by brute force, independent of the renderer and of its
// Embree reference: what a test compares the renderer's shadows with.

#include <glm/glm.hpp>
#include <vector>

namespace omnishadow::test_support {

struct WorldTriangle {
  glm::vec3 a, b, c;
};

// Möller-Trumbore: does the open segment from `from` to `to` cross any of the triangles? Ends
// within 1e-4 of the segment's length of a crossing do not count.
bool segmentBlocked(const std::vector<WorldTriangle>& triangles, glm::vec3 from, glm::vec3 to);

}  // namespace omnishadow::test_support
