#include "renderer/view/camera_sets.h"

#include <cmath>
#include <numbers>

namespace omnishadow {

std::vector<CameraView> orbitViews(const glm::vec3& eye, const glm::vec3& center, int count) {
  const glm::vec3 d = eye - center;
  float radius = std::hypot(d.x, d.z);
  float height = d.y;
  const float distance = glm::length(d);
  if (radius < 1e-6f * distance) {
    radius = distance * std::cos(std::numbers::pi_v<float> / 6);
    height = distance * std::sin(std::numbers::pi_v<float> / 6);
  }
  const float start = std::atan2(d.x, d.z);
  std::vector<CameraView> views;
  for (int k = 0; k < count; ++k) {
    const float a = start + 2.0f * std::numbers::pi_v<float> * static_cast<float>(k) /
                                static_cast<float>(count);
    views.push_back(
        {center + glm::vec3(radius * std::sin(a), height, radius * std::cos(a)), center});
  }
  return views;
}

std::vector<CameraView> hemisphereViews(const glm::vec3& center, float distance, int count) {
  const float golden = std::numbers::pi_v<float> * (3.0f - std::sqrt(5.0f));
  std::vector<CameraView> views;
  for (int k = 0; k < count; ++k) {
    const float y = 1.0f - (static_cast<float>(k) + 0.5f) / static_cast<float>(count);
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    const float phi = golden * static_cast<float>(k);
    views.push_back(
        {center + distance * glm::vec3(r * std::cos(phi), y, r * std::sin(phi)), center});
  }
  return views;
}

}  // namespace omnishadow
