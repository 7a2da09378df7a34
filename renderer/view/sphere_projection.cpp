#include "renderer/view/sphere_projection.h"

#include <limits>

namespace omnishadow {

namespace {

// The hull of the projected corners of the box from `low` to `high` under `toClip`.
// Flattened: glm's matrix-vector product is otherwise called out of line, eight times per
// sphere and view, for every caster a light keeps (the same arithmetic either way).
[[gnu::flatten]] std::optional<NdcBounds> projectedCorners(const glm::mat4& toClip,
                                                           const glm::vec3& low,
                                                           const glm::vec3& high) {
  // The box lies in front of the eye when all its corners do (w is linear in position).
  NdcBounds bounds{glm::vec2(std::numeric_limits<float>::max()),
                   glm::vec2(std::numeric_limits<float>::lowest())};
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? high.x : low.x, (corner & 2) ? high.y : low.y,
                      (corner & 4) ? high.z : low.z);
    const glm::vec4 clip = toClip * glm::vec4(p, 1.0f);
    if (!(clip.w > 0.0f)) return std::nullopt;
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    bounds.low = glm::min(bounds.low, ndc);
    bounds.high = glm::max(bounds.high, ndc);
  }
  return bounds;
}

}  // namespace

std::optional<NdcBounds> projectedSphereBox(const glm::mat4& viewProjection,
                                            const glm::vec3& center, float radius) {
  return projectedCorners(viewProjection, center - radius, center + radius);
}

std::optional<NdcBounds> projectedBox(const glm::mat4& viewProjection, const glm::mat4& model,
                                      const glm::vec3& low, const glm::vec3& high) {
  return projectedCorners(viewProjection * model, low, high);
}

}  // namespace omnishadow
