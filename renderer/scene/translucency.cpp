#include "renderer/scene/translucency.h"

#include <cmath>

namespace omnishadow {

bool isTranslucentCaster(const Material& material) {
  return material.alphaMode == AlphaMode::Blend || material.transmissionFactor > 0.0f ||
         hasDiffuseTransmission(material);
}

glm::vec3 volumeAttenuationExponent(const Material& material, float scale) {
  if (!hasVolume(material) || !std::isfinite(material.attenuationDistance)) return glm::vec3(0.0f);
  // As the lighting pass's Beer's law: a color of 0 absorbs all but 1e-30.
  return glm::log(glm::max(material.attenuationColor, glm::vec3(1e-30f))) *
         (material.thicknessFactor * scale / (2.0f * material.attenuationDistance));
}

float volumeScale(const glm::mat4& world) {
  return std::cbrt(std::abs(glm::determinant(glm::mat3(world))));
}

glm::vec3 surfaceTransmittance(const Material& material, const SurfaceTexels& texels,
                               float volumeScale) {
  const glm::vec4& base = texels.baseColor;
  float alpha = 1.0f;
  if (material.alphaMode == AlphaMode::Blend) alpha = glm::clamp(base.a, 0.0f, 1.0f);
  if (material.alphaMode == AlphaMode::Mask && base.a < material.alphaCutoff) return {1, 1, 1};
  // In the order the shader multiplies (shadow_transmittance.frag), so that a material without
  // a volume or diffuse transmission gives the same float as before they counted.
  const glm::vec3 color = glm::clamp(glm::vec3(base), 0.0f, 1.0f) *
                          glm::exp(volumeAttenuationExponent(material, volumeScale) *
                                   glm::clamp(texels.thickness, 0.0f, 1.0f));
  const float transmission =
      material.transmissionFactor * glm::clamp(texels.transmission, 0.0f, 1.0f);
  glm::vec3 t = glm::vec3(1.0f - alpha) + alpha * transmission * color;
  if (hasDiffuseTransmission(material)) {
    t += alpha * (1.0f - transmission) * material.diffuseTransmissionFactor *
         glm::clamp(texels.diffuseTransmission, 0.0f, 1.0f) *
         (material.diffuseTransmissionColorFactor *
          glm::clamp(texels.diffuseTransmissionColor, 0.0f, 1.0f));
  }
  return t;
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
