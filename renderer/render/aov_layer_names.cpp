#include "renderer/render/aov_layer_names.h"

#include <utility>

namespace omnishadow {

bool enableAovLayer(AovLayers& layers, const std::string& name) {
  const std::pair<const char*, bool AovLayers::*> names[] = {
      {"albedo", &AovLayers::albedo},         {"roughness", &AovLayers::roughness},
      {"metallic", &AovLayers::metallic},     {"diffuse", &AovLayers::diffuse},
      {"specular", &AovLayers::specular},     {"objectId", &AovLayers::objectId},
      {"materialId", &AovLayers::materialId}, {"occlusion", &AovLayers::occlusion}};
  bool known = name == "all";
  for (const auto& [layer, member] : names)
    if (name == "all" || name == layer) {
      layers.*member = true;
      known = true;
    }
  return known;
}

}  // namespace omnishadow
