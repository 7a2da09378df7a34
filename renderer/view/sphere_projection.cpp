#include "renderer/view/sphere_projection.h"

#include <limits>

namespace omnishadow {

// Flattened: glm's matrix-vector product is otherwise called out of line, eight times per
// sphere and view, for every caster a light keeps (the same arithmetic either way).
[[gnu::flatten]] std::optional<NdcBounds> projectedSphereBox(const glm::mat4& viewProjection,
                                                             const glm::vec3& center,
                                                             float radius) {
  // The box lies in front of the eye when all its corners do (w is linear in position).
  NdcBounds bounds{glm::vec2(std::numeric_limits<float>::max()),
                   glm::vec2(std::numeric_limits<float>::lowest())};
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 offset((corner & 1) ? radius : -radius, (corner & 2) ? radius : -radius,
                           (corner & 4) ? radius : -radius);
    const glm::vec4 clip = viewProjection * glm::vec4(center + offset, 1.0f);
    if (!(clip.w > 0.0f)) return std::nullopt;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    bounds.low = glm::min(bounds.low, ndc);
    bounds.high = glm::max(bounds.high, ndc);
  }
  return bounds;
}

}  // namespace omnishadow
