#include "tests/support/segment_occlusion.h"

#include <cmath>

namespace omnishadow::test_support {

bool segmentBlocked(const std::vector<WorldTriangle>& triangles, glm::vec3 from, glm::vec3 to) {
  const glm::vec3 d = to - from;
  for (const WorldTriangle& t : triangles) {
    const glm::vec3 e1 = t.b - t.a, e2 = t.c - t.a;
    const glm::vec3 p = glm::cross(d, e2);
    const float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-12f) continue;
    const glm::vec3 s = from - t.a;
    const float u = glm::dot(s, p) / det;
    if (u < 0.0f || u > 1.0f) continue;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) / det;
    if (v < 0.0f || u + v > 1.0f) continue;
    const float hit = glm::dot(e2, q) / det;
    if (hit > 1e-4f && hit < 1.0f - 1e-4f) return true;
  }
  return false;
}

}  // namespace omnishadow::test_support
