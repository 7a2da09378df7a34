#pragma once

#include <glm/glm.hpp>

namespace omnishadow {

// Axis-aligned box; starts empty and grows with extend().
struct Bounds {
  glm::vec3 min{1e30f};
  glm::vec3 max{-1e30f};

  bool empty() const { return min.x > max.x; }
  void extend(const glm::vec3& p);
  void extend(const Bounds& other);
  glm::vec3 center() const { return (min + max) * 0.5f; }
  // Radius of the sphere around center() that holds the box.
  float radius() const { return empty() ? 0.0f : glm::length(max - min) * 0.5f; }
  Bounds transformed(const glm::mat4& m) const;
};

}  // namespace omnishadow
