#pragma once

// Rendering a scene's AOVs and checking its shadows against exact rays, as the shadow quality
// tests do it.

#include <glm/glm.hpp>
#include <vector>

#include "renderer/render/renderer.h"
#include "renderer/scene/scene.h"
#include "renderer/verify/shadow_verification.h"
#include "renderer/view/camera.h"
#include "renderer/view/shadow_plan.h"

namespace omnishadow::test {

inline Frame renderAovs(Renderer& renderer, const Scene& scene, const std::vector<Light>& lights,
                        const ViewCamera& camera) {
  RenderSettings settings;
  settings.aovs = true;
  StageTimes times;
  return renderer.render(scene, lights, glm::vec3(0.03f), camera, settings, times);
}

// verifyShadows() of every light with default settings, each with its effective shadow far.
inline ShadowVerification verifyAgainstRays(const Scene& scene, const std::vector<Light>& lights,
                                            const Frame& frame, const ViewCamera& camera) {
  std::vector<LightToVerify> targets;
  for (const Light& light : lights)
    targets.push_back({light, effectiveShadowFar(light, scene.bounds)});
  const ShadowReference reference(scene);
  return verifyShadows(reference, scene.bounds, targets, *frame.aovs, camera, VerifySettings{});
}

}  // namespace omnishadow::test
