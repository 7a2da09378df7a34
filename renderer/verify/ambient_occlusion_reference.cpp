#include "renderer/verify/ambient_occlusion_reference.h"

#include <algorithm>
#include <cmath>

#include "renderer/scene/tangents.h"

namespace omnishadow {

float ambientVisibility(const ShadowReference& reference, const glm::vec3& point,
                        const glm::vec3& normal, float reach, int samples) {
  const int side = std::max(1, static_cast<int>(std::sqrt(static_cast<float>(samples))));
  // Any frame around the normal: the grid covers the whole disk either way.
  const glm::vec3 n = glm::normalize(normal);
  const glm::vec3 t = anyPerpendicular(n);
  const glm::vec3 b = glm::cross(n, t);
  const glm::vec3 origin = point + n * reference.epsilon();
  int open = 0;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      // Cosine-weighted: uniform on the unit disk (Malley), lifted to the hemisphere.
      const float u = (static_cast<float>(i) + 0.5f) / static_cast<float>(side);
      const float phi = 6.2831853f * (static_cast<float>(j) + 0.5f) / static_cast<float>(side);
      const float r = std::sqrt(u);
      const glm::vec3 direction =
          t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(1.0f - u);
      open += reference.occluded(origin, glm::normalize(direction), 0.0f, reach) ? 0 : 1;
    }
  return static_cast<float>(open) / static_cast<float>(side * side);
}

}  // namespace omnishadow
