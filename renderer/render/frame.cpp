#include "renderer/render/frame.h"

#include "renderer/core/errors.h"

namespace omnishadow {

std::vector<std::string> aovChannels(const std::vector<Light>& lights, const AovLayers& layers,
                                     const std::vector<bool>& translucent) {
  std::vector<std::string> channels = {"R",   "G",   "B",   "A",   "P.X", "P.Y",
                                       "P.Z", "N.X", "N.Y", "N.Z", "Z"};
  for (const Light& light : lights) channels.push_back("visibility." + light.name);
  if (layers.albedo)
    for (const char* c : {"R", "G", "B"}) channels.push_back(std::string("albedo.") + c);
  if (layers.roughness) channels.push_back("roughness");
  if (layers.metallic) channels.push_back("metallic");
  if (layers.objectId) channels.push_back("objectId");
  if (layers.materialId) channels.push_back("materialId");
  if (layers.occlusion) channels.push_back("occlusion");
  for (const Light& light : lights) {
    if (layers.diffuse)
      for (const char* c : {"R", "G", "B"}) channels.push_back("diffuse." + light.name + "." + c);
    if (layers.specular)
      for (const char* c : {"R", "G", "B"}) channels.push_back("specular." + light.name + "." + c);
  }
  for (std::size_t i = 0; i < lights.size() && i < translucent.size(); ++i)
    if (translucent[i])
      for (const char* c : {"R", "G", "B"})
        channels.push_back("transmittance." + lights[i].name + "." + c);
  return channels;
}

const FloatImage& objectIdImage(const Frame& frame) {
  if (frame.aovs && frame.aovs->channelIndex("objectId") >= 0) return *frame.aovs;
  if (frame.objectIds) return *frame.objectIds;
  throw RenderError("annotation masks need the objectId AOV layer");
}

}  // namespace omnishadow
