#include "renderer/scene/translucency.h"

namespace omnishadow {

bool isTranslucentCaster(const Material& material) {
  return material.alphaMode == AlphaMode::Blend || material.transmissionFactor > 0.0f;
}

glm::vec3 surfaceTransmittance(const Material& material, const glm::vec4& baseColor,
                               float transmissionTexel) {
  float alpha = 1.0f;
  if (material.alphaMode == AlphaMode::Blend) alpha = glm::clamp(baseColor.a, 0.0f, 1.0f);
  if (material.alphaMode == AlphaMode::Mask && baseColor.a < material.alphaCutoff) return {1, 1, 1};
  const glm::vec3 color = glm::clamp(glm::vec3(baseColor), 0.0f, 1.0f);
  const float transmission =
      material.transmissionFactor * glm::clamp(transmissionTexel, 0.0f, 1.0f);
  return glm::vec3(1.0f - alpha) + alpha * transmission * color;
}

bool hasTranslucentCasters(const Scene& scene) {
  for (const MeshInstance& instance : scene.instances) {
    if (instance.mesh < 0 || instance.mesh >= static_cast<int>(scene.meshes.size())) continue;
    const Mesh& mesh = scene.meshes[instance.mesh];
    if (mesh.indices.empty() || mesh.material < 0 ||
        mesh.material >= static_cast<int>(scene.materials.size()))
      continue;
    if (isTranslucentCaster(scene.materials[mesh.material])) return true;
  }
  return false;
}

bool castsTranslucentShadows(const Light& light) {
  return light.shadow.enabled && light.shadow.translucent &&
         light.shadow.filter != ShadowFilter::Vsm;
}

std::vector<bool> translucentShadowLights(const std::vector<Light>& lights, const Scene& scene) {
  const bool any = hasTranslucentCasters(scene);
  std::vector<bool> result;
  for (const Light& light : lights) result.push_back(any && castsTranslucentShadows(light));
  return result;
}

}  // namespace omnishadow
