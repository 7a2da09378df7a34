#pragma once

#include <array>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "renderer/scene/bounds.h"
#include "renderer/scene/light.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// Shadow maps of one frame live in a few array textures: point lights in cube map arrays,
// spot lights and directional cascades in 2D arrays ("planar"). Lights whose maps share a
// resolution, depth format and filter family share one texture (a group), so a frame with 256
// shadowed point lights samples one or two textures instead of 256.

enum class ShadowLayout { Cube, Planar };

struct ShadowGroupKey {
  ShadowLayout layout = ShadowLayout::Cube;
  int resolution = 0;
  DepthFormat format = DepthFormat::Float32;
  bool moments = false;  // vsm: an RG32F moment texture with the same layers
  bool operator==(const ShadowGroupKey& o) const {
    return layout == o.layout && resolution == o.resolution && format == o.format &&
           moments == o.moments;
  }
};

// Groups per layout the lighting shader can sample (texture units, see shaders/shadows.glsl).
inline constexpr int kMaxShadowGroups = 4;

struct ShadowGroupPlan {
  ShadowGroupKey key;
  int layers = 0;  // cube map arrays: layer-faces, 6 per light
};

// One shadowed light: where its layers are and how they were projected.
struct LightShadowPlan {
  int light = -1;  // index into the frame's lights
  int group = -1;  // index into ShadowAtlasPlan::groups
  int firstLayer = 0;
  int layerCount = 0;  // 6 (point), 1 (spot) or the cascade count (directional)
  std::array<glm::mat4, 6> viewProjection{};
  float near = 0.0f;        // point, spot: depth range along the view axis; directional: the range
  float far = 0.0f;         // of distances along the light direction
  float tanHalfFov = 0.0f;  // spot
  std::array<float, 4> cascadeEnd{};    // directional: camera view depth per cascade
  std::array<float, 4> cascadeTexel{};  // directional: world texel size per cascade
  glm::vec3 position{0.0f};             // point: the cube's center
};

struct ShadowAtlasPlan {
  std::vector<ShadowGroupPlan> groups;
  std::vector<LightShadowPlan> lights;  // shadowed lights only, in light order
  double bytes = 0.0;                   // GPU memory of all groups
  std::vector<std::string> warnings;
};

struct ShadowLimits {
  int maxArrayLayers = 2048;  // GL_MAX_ARRAY_TEXTURE_LAYERS
};

// Decides groups, layers and projections for every shadowed light. `far` of point and spot
// lights is effectiveShadowFar(). Throws InputError when more groups are needed than the
// shader can sample.
ShadowAtlasPlan planShadowAtlas(const std::vector<Light>& lights, const ViewCamera& camera,
                                const Bounds& sceneBounds, const ShadowLimits& limits);

// Shadow far plane of a point or spot light: its `far` when set, else its range, else the
// farthest corner of the scene.
float effectiveShadowFar(const Light& light, const Bounds& sceneBounds);

// Shadow near plane of a point or spot light: its `near` when set, else a length that scales
// with the scene and the light (README, "Scale-free defaults"): half of what the nearest point
// of the scene bounds can be along the map's view axis (so nothing in the scene is clipped when
// the light is outside it), but at least kAutoNearFraction of the far plane (so float depth
// keeps its precision when the light is inside the scene), and at most half the far plane.
inline constexpr float kAutoNearFraction = 1e-3f;
float effectiveShadowNear(const Light& light, const Bounds& sceneBounds);

}  // namespace omnishadow
