#pragma once
// What the in-process rendering tests share: one GL context per test program, and a camera
// looking from one point at another.
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

}  // namespace omnishadow::test_support
