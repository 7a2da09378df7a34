#include "renderer/render/frame_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "renderer/core/errors.h"
#include "renderer/render/antialiasing.h"
#include "renderer/scene/translucency.h"

namespace omnishadow {
namespace {

void checkResolutions(const std::vector<Light>& lights, const RenderLimits& limits) {
  for (const Light& light : lights) {
    if (!light.shadow.enabled) continue;
    const bool cube = light.type == LightType::Point;
    const int limit = cube ? limits.maxCubeMapSize : limits.maxTextureSize;
    if (light.shadow.resolution > limit)
      throw InputError(light.origin + ": light \"" + light.name + "\": shadow.resolution " +
                       std::to_string(light.shadow.resolution) + " exceeds this GL's maximum " +
                       (cube ? "cube map" : "texture") + " size " + std::to_string(limit));
  }
}

int findCascadeDebugLight(const std::vector<Light>& lights, const RenderSettings& settings) {
  for (std::size_t i = 0; i < lights.size(); ++i)
    if (lights[i].shadow.enabled && lights[i].type == LightType::Directional &&
        (settings.debugLight.empty() || lights[i].name == settings.debugLight))
      return static_cast<int>(i);
  throw InputError(settings.debugLight.empty()
                       ? "--debug-view cascade: no directional light casts a shadow"
                       : "--debug-light " + settings.debugLight +
                             ": no shadowed directional light has that name");
}

// Inside the CLI's range (16384) a frame may still be more than the GL allocates: refused here,
// naming the limit, instead of failing at framebuffer creation.
void checkFrameSize(const ViewCamera& camera, const RenderLimits& limits) {
  const long long texels = static_cast<long long>(camera.width) * camera.height;
  if (camera.width > limits.maxTextureSize || camera.height > limits.maxTextureSize ||
      texels > limits.maxFrameTexels) {
    const auto side = static_cast<long long>(std::sqrt(static_cast<double>(limits.maxFrameTexels)));
    throw InputError("--width/--height " + std::to_string(camera.width) + "x" +
                     std::to_string(camera.height) + ": more than this GL allocates for a frame (" +
                     std::to_string(limits.maxFrameTexels) + " texels, e.g. " +
                     std::to_string(side) + "x" + std::to_string(side) + ", at most " +
                     std::to_string(limits.maxTextureSize) + " per side)");
  }
}

int findDebugLight(const std::vector<Light>& lights, const RenderSettings& settings) {
  if (settings.debugView == DebugView::Cascade) return findCascadeDebugLight(lights, settings);
  if (settings.debugView != DebugView::Depth) return -1;
  for (std::size_t i = 0; i < lights.size(); ++i)
    if (lights[i].shadow.enabled &&
        (settings.debugLight.empty() || lights[i].name == settings.debugLight))
      return static_cast<int>(i);
  throw InputError(settings.debugLight.empty() ? "--debug-view depth: no light casts a shadow"
                                               : "--debug-light " + settings.debugLight +
                                                     ": no shadowed light has that name");
}

// GPU memory of the RGBA32F transmittance atlas (renderer/passes/transmittance_pass.h) at most:
// every shadow layer of every light with translucent shadows, and its scratch layer, at the
// largest of their resolutions (the atlas holds only the layers and texels translucent casters
// reach).
double transmittanceBytes(const ShadowAtlasPlan& atlas, const std::vector<Light>& lights,
                          const Scene& scene) {
  const std::vector<bool> translucent = translucentShadowLights(lights, scene);
  double layers = 0.0, resolution = 0.0;
  for (const LightShadowPlan& light : atlas.lights) {
    if (!translucent[static_cast<std::size_t>(light.light)]) continue;
    layers += light.layerCount;
    resolution = std::max(
        resolution,
        static_cast<double>(atlas.groups[static_cast<std::size_t>(light.group)].key.resolution));
  }
  return layers > 0.0 ? 16.0 * resolution * resolution * (layers + 1.0) : 0.0;
}

}  // namespace

FramePlan planFrame(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
                    const RenderSettings& settings, const RenderLimits& limits) {
  checkResolutions(lights, limits);
  checkAntialiasingSampleCount(settings.antialiasing);
  checkFrameSize(camera, limits);
  FramePlan plan;
  plan.shadows = planShadowAtlas(lights, camera, scene.bounds, ShadowLimits{limits.maxArrayLayers});
  plan.shadows.bytes += transmittanceBytes(plan.shadows, lights, scene);
  const double shadowMiB = plan.shadows.bytes / (1024.0 * 1024.0);
  if (shadowMiB > settings.maxShadowMemoryMiB) {
    char message[256];
    std::snprintf(message, sizeof message,
                  "the shadow maps need %.0f MiB, more than the %.0f MiB allowed "
                  "(--max-memory): lower shadow.resolution",
                  shadowMiB, settings.maxShadowMemoryMiB);
    throw InputError(message);
  }
  plan.warnings = plan.shadows.warnings;
  plan.debugLight = findDebugLight(lights, settings);
  return plan;
}

}  // namespace omnishadow
