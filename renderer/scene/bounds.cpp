#include "renderer/scene/bounds.h"

namespace omnishadow {

void Bounds::extend(const glm::vec3& p) {
  min = glm::min(min, p);
  max = glm::max(max, p);
}

void Bounds::extend(const Bounds& other) {
  if (other.empty()) return;
  extend(other.min);
  extend(other.max);
}

Bounds Bounds::transformed(const glm::mat4& m) const {
  Bounds out;
  if (empty()) return out;
  for (int corner = 0; corner < 8; ++corner) {
    glm::vec3 p{(corner & 1) ? max.x : min.x, (corner & 2) ? max.y : min.y,
                (corner & 4) ? max.z : min.z};
    out.extend(glm::vec3(m * glm::vec4(p, 1.0f)));
  }
  return out;
}

}  // namespace omnishadow
