#include "renderer/view/headlight.h"

#include <algorithm>

namespace omnishadow {

Light headlight(const ViewCamera& camera, const Bounds& bounds) {
  Light light;
  light.name = "headlight";
  const glm::vec3 up = glm::vec3(glm::inverse(camera.view)[1]);
  const float radius = std::max(bounds.radius(), 1e-3f);
  light.position = camera.eye + up * radius * 0.3f;
  const float distance = glm::length(bounds.center() - light.position);
  light.intensity = distance * distance;  // about 1 lux at the scene center
  light.origin = "default";
  return light;
}

}  // namespace omnishadow
