#pragma once
// A small stage for shadow tests: a floor, a sphere, an alpha-tested box (the shadow pass's
// masked path) and a blue glass slab (translucent shadows, the float beauty).
#include <glm/gtc/matrix_transform.hpp>

#include "renderer/scene/scene.h"
#include "tests/support/scene_objects.h"

namespace omnishadow::test_support {

inline Scene shadowStage() {
  Scene scene;
  Material white;
  white.baseColorFactor = glm::vec4(0.8f);
  white.metallicFactor = 0.0f;
  Material masked = white;  // drawn one by one by the shadow pass's alpha-tested path
  masked.alphaMode = AlphaMode::Mask;
  masked.baseColorFactor = glm::vec4(0.6f, 0.7f, 0.8f, 0.9f);
  Material glass = white;  // tints the lights with translucent shadows (transmittance pass)
  glass.alphaMode = AlphaMode::Blend;
  glass.baseColorFactor = glm::vec4(0.2f, 0.6f, 1.0f, 0.5f);
  glass.doubleSided = true;
  scene.materials = {white, masked, glass};
  test::placeMesh(scene, builder::makePlane(8.0f), glm::mat4(1.0f), 0);
  test::placeMesh(scene, builder::makeSphere(0.5f, 24, 12),
                  glm::translate(glm::mat4(1.0f), {0.0f, 1.0f, 0.0f}), 0);
  test::placeMesh(scene, builder::makeBox(glm::vec3(0.4f)),
                  glm::translate(glm::mat4(1.0f), {1.2f, 0.4f, -0.6f}), 1);
  test::placeMesh(scene, builder::makeBox(glm::vec3(0.5f, 0.05f, 0.5f)),
                  glm::translate(glm::mat4(1.0f), {-1.0f, 1.2f, 0.5f}), 2);
  return scene;
}

}  // namespace omnishadow::test_support
