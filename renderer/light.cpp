#include "renderer/light.h"

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

}  // namespace omnishadow
