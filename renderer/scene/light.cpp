#include "renderer/scene/light.h"

#include <algorithm>

namespace omnishadow {

const char* toString(LightType type) {
  switch (type) {
    case LightType::Point:
      return "point";
    case LightType::Spot:
      return "spot";
    case LightType::Directional:
      return "directional";
  }
  return "?";
}

const char* toString(ShadowFilter filter) {
  switch (filter) {
    case ShadowFilter::Hard:
      return "hard";
    case ShadowFilter::Pcf:
      return "pcf";
    case ShadowFilter::PcfDisk:
      return "pcf-disk";
    case ShadowFilter::Poisson:
      return "poisson";
    case ShadowFilter::Pcss:
      return "pcss";
    case ShadowFilter::Vsm:
      return "vsm";
  }
  return "?";
}

const char* toString(CullFace cull) {
  switch (cull) {
    case CullFace::None:
      return "none";
    case CullFace::Back:
      return "back";
    case CullFace::Front:
      return "front";
  }
  return "?";
}

const char* toString(DepthFormat format) {
  switch (format) {
    case DepthFormat::Float32:
      return "32f";
    case DepthFormat::Fixed24:
      return "24";
  }
  return "?";
}

std::vector<Light> mergeLights(const std::vector<Light>& gltfLights,
                               const std::vector<Light>& fileLights) {
  std::vector<Light> merged;
  for (const Light& light : gltfLights) {
    const bool replaced = std::any_of(fileLights.begin(), fileLights.end(),
                                      [&](const Light& l) { return l.name == light.name; });
    if (!replaced) merged.push_back(light);
  }
  merged.insert(merged.end(), fileLights.begin(), fileLights.end());
  return merged;
}

float effectiveRadius(const AmbientOcclusion& occlusion, const Bounds& sceneBounds) {
  if (occlusion.radius > 0.0f) return occlusion.radius;
  return kDefaultAmbientOcclusionShare * 2.0f * sceneBounds.radius();
}

}  // namespace omnishadow
