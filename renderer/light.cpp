#include "renderer/light.h"

#include <algorithm>
#include <set>

namespace omnishadow {

const char* toString(LightType type) {
  switch (type) {
    case LightType::Point: return "point";
    case LightType::Spot: return "spot";
    case LightType::Directional: return "directional";
  }
  return "?";
}

const char* toString(ShadowFilter filter) {
  switch (filter) {
    case ShadowFilter::Hard: return "hard";
    case ShadowFilter::Pcf: return "pcf";
    case ShadowFilter::PcfDisk: return "pcf-disk";
  }
  return "?";
}

std::vector<Light> mergeLights(const std::vector<Light>& gltfLights,
                               const std::vector<Light>& fileLights) {
  std::set<std::string> names;
  for (const Light& light : fileLights) names.insert(light.name);
  std::vector<Light> merged;
  for (const Light& light : gltfLights) {
    if (names.count(light.name) && std::any_of(fileLights.begin(), fileLights.end(),
                                               [&](const Light& l) { return l.name == light.name; }))
      continue;  // replaced by the lights file
    // glTF does not require unique light names; AOV channels do.
    Light renamed = light;
    for (int suffix = 2; names.count(renamed.name); ++suffix)
      renamed.name = light.name + "_" + std::to_string(suffix);
    names.insert(renamed.name);
    merged.push_back(std::move(renamed));
  }
  merged.insert(merged.end(), fileLights.begin(), fileLights.end());
  return merged;
}

}  // namespace omnishadow
