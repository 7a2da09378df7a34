#pragma once

#include <glm/glm.hpp>
#include <optional>

namespace omnishadow {

// NDC x and y bounds of a projected shape.
struct NdcBounds {
  glm::vec2 low{0.0f}, high{0.0f};
};

// The NDC bounds of a sphere's bounding box under `viewProjection`: the hull of its eight
// projected corners. Nothing when a corner is not in front of the eye (clip w <= 0), where the
// corners no longer bound the projection.
std::optional<NdcBounds> projectedSphereBox(const glm::mat4& viewProjection,
                                            const glm::vec3& center, float radius);
// The same for a box given in the space `model` places in the world: `low` and `high` are its
// opposite corners there.
std::optional<NdcBounds> projectedBox(const glm::mat4& viewProjection, const glm::mat4& model,
                                      const glm::vec3& low, const glm::vec3& high);

}  // namespace omnishadow
