#include "renderer/view/shadow_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/core/errors.h"
#include "renderer/view/cube_faces.h"
#include "renderer/view/shadow_views.h"

namespace omnishadow {

namespace {

double bytesPerTexel(const ShadowGroupKey& key) {
  return 4.0 + (key.moments ? 8.0 : 0.0);  // 24-bit depth is stored in 32 bits
}

const char* layoutName(ShadowLayout layout) {
  return layout == ShadowLayout::Cube ? "point" : "spot/directional";
}

}  // namespace

float effectiveShadowFar(const Light& light, const Bounds& sceneBounds) {
  if (light.shadow.far > 0.0f) return light.shadow.far;
  if (light.range > 0.0f) return light.range;
  // Far enough for every point of the scene, with a margin so the farthest corner is inside.
  float farthest = 0.0f;
  if (!sceneBounds.empty()) {
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p{(corner & 1) ? sceneBounds.max.x : sceneBounds.min.x,
                        (corner & 2) ? sceneBounds.max.y : sceneBounds.min.y,
                        (corner & 4) ? sceneBounds.max.z : sceneBounds.min.z};
      farthest = std::max(farthest, glm::length(p - light.position));
    }
  }
  return std::max(farthest * 1.01f, light.shadow.near * 2.0f);
}

float effectiveShadowNear(const Light& light, const Bounds& sceneBounds) {
  if (light.shadow.near > 0.0f) return light.shadow.near;
  const float far = effectiveShadowFar(light, sceneBounds);
  float outside = 0.0f;  // distance from the light to the scene's box, 0 inside it
  if (!sceneBounds.empty()) {
    const glm::vec3 nearest = glm::clamp(light.position, sceneBounds.min, sceneBounds.max);
    outside = glm::length(nearest - light.position);
  }
  // A cube face's axis distance is at least 1/sqrt(3) of the distance; a spot map's view depth
  // at least cos(half angle) of it, for points inside its frustum.
  const float axisShare = light.type == LightType::Spot
                              ? std::cos(std::min(light.outerConeAngle, kMaxSpotShadowHalfAngle))
                              : 0.57735026919f;
  const float near = std::max(0.5f * outside * axisShare, kAutoNearFraction * far);
  return far > 0.0f ? std::min(near, 0.5f * far) : 1.0f;
}

ShadowAtlasPlan planShadowAtlas(const std::vector<Light>& lights, const ViewCamera& camera,
                                const Bounds& sceneBounds, const ShadowLimits& limits) {
  ShadowAtlasPlan plan;
  // A group is found by key and by room: past the layer limit a key opens another group.
  auto place = [&](const ShadowGroupKey& key, int layers) {
    for (std::size_t g = 0; g < plan.groups.size(); ++g) {
      ShadowGroupPlan& group = plan.groups[g];
      if (group.key == key && group.layers + layers <= limits.maxArrayLayers) {
        group.layers += layers;
        return std::make_pair(static_cast<int>(g), group.layers - layers);
      }
    }
    const auto sameLayout =
        std::count_if(plan.groups.begin(), plan.groups.end(),
                      [&](const auto& g) { return g.key.layout == key.layout; });
    // The advice follows the cause: lights alike that fill every texture's layers, or lights
    // of so many kinds that each needs its own texture.
    const bool full = std::any_of(plan.groups.begin(), plan.groups.end(),
                                  [&](const auto& g) { return g.key == key; });
    if (sameLayout >= kMaxShadowGroups)
      throw InputError(std::string("the ") + layoutName(key.layout) +
                       " lights' shadow maps need more than " + std::to_string(kMaxShadowGroups) +
                       " textures (one per resolution, depth format and vsm or not, " +
                       std::to_string(limits.maxArrayLayers) + " layers each): " +
                       (full ? "use fewer shadowed lights (or \"shadow\": false on some)"
                             : "use fewer distinct shadow resolutions"));
    plan.groups.push_back({key, layers});
    return std::make_pair(static_cast<int>(plan.groups.size() - 1), 0);
  };

  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    if (!light.shadow.enabled) continue;
    LightShadowPlan shadow;
    shadow.light = static_cast<int>(i);
    ShadowGroupKey key;
    key.resolution = light.shadow.resolution;
    key.format = light.shadow.depthFormat;
    key.moments = light.shadow.filter == ShadowFilter::Vsm;
    switch (light.type) {
      case LightType::Point: {
        key.layout = ShadowLayout::Cube;
        shadow.layerCount = kCubeFaceCount;
        shadow.near = effectiveShadowNear(light, sceneBounds);
        shadow.far = effectiveShadowFar(light, sceneBounds);
        shadow.position = light.position;
        const glm::mat4 projection = cubeFaceProjection(shadow.near, shadow.far);
        for (int face = 0; face < kCubeFaceCount; ++face)
          shadow.viewProjection[face] =
              projection * cubeFaceView(static_cast<CubeFace>(face), light.position);
        break;
      }
      case LightType::Spot: {
        key.layout = ShadowLayout::Planar;
        shadow.layerCount = 1;
        shadow.near = effectiveShadowNear(light, sceneBounds);
        shadow.far = effectiveShadowFar(light, sceneBounds);
        shadow.position = light.position;
        const SpotShadowFrame frame =
            spotShadowFrame(light, shadow.near, shadow.far, light.shadow.resolution);
        shadow.viewProjection[0] = frame.viewProjection;
        shadow.tanHalfFov = frame.tanHalfFov;
        if (frame.coneClipped)
          plan.warnings.push_back("light \"" + light.name +
                                  "\": the spot cone is wider than the 170 degrees one shadow map "
                                  "covers; the part outside is lit unshadowed");
        break;
      }
      case LightType::Directional: {
        key.layout = ShadowLayout::Planar;
        const DirectionalShadowFrame frame = directionalShadowFrame(light, camera, sceneBounds);
        shadow.layerCount = static_cast<int>(frame.cascades.size());
        shadow.near = frame.nearToLight;
        shadow.far = frame.farFromLight;
        for (std::size_t c = 0; c < frame.cascades.size(); ++c) {
          shadow.viewProjection[c] = frame.cascades[c].viewProjection;
          shadow.cascadeEnd[c] = frame.cascades[c].viewDepthEnd;
          shadow.cascadeTexel[c] = frame.cascades[c].texelSize;
        }
        break;
      }
    }
    const auto [group, first] = place(key, shadow.layerCount);
    shadow.group = group;
    shadow.firstLayer = first;
    plan.lights.push_back(shadow);
  }
  for (const ShadowGroupPlan& group : plan.groups)
    plan.bytes += bytesPerTexel(group.key) * group.layers *
                  static_cast<double>(group.key.resolution) * group.key.resolution;
  return plan;
}

}  // namespace omnishadow
