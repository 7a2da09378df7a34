#pragma once
// What the in-process rendering tests share: one GL context per test program, and a camera
// looking from one point at another.
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/render/renderer.h"
#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"

namespace omnishadow::test_support {

// One context for the whole program: creating one costs about a second on llvmpipe.
inline Renderer& sharedRenderer() {
  static Renderer renderer(ContextOptions{});
  return renderer;
}

// A perspective camera at `eye` looking at `target`, `fov` degrees vertically.
inline ViewCamera lookFrom(const Scene& scene, glm::vec3 eye, glm::vec3 target, int width,
                           int height, float fov = 60.0f, glm::vec3 up = {0, 1, 0}) {
  return resolveCamera(scene, {.eye = eye,
                               .target = target,
                               .up = up,
                               .fovDegrees = fov,
                               .width = width,
                               .height = height});
}

// A frame with AOVs from the shared context, `ambient` the ambient radiance.
inline Frame renderWithAovs(const Scene& scene, const std::vector<Light>& lights,
                            const ViewCamera& camera, RenderSettings settings = {},
                            glm::vec3 ambient = glm::vec3(0.0f)) {
  settings.aovs = true;
  StageTimes times;
  return sharedRenderer().render(scene, lights, ambient, camera, settings, times);
}

// The 8-bit sRGB beauty (RGB bytes) from the shared context, at exposure 0.
inline std::vector<std::uint8_t> renderSrgb8(const Scene& scene, const std::vector<Light>& lights,
                                             const ViewCamera& camera, glm::vec3 ambient) {
  RenderSettings settings;
  settings.srgb8Exposure = 0.0f;
  StageTimes times;
  return sharedRenderer().render(scene, lights, ambient, camera, settings, times).srgb8->rgb;
}

}  // namespace omnishadow::test_support
