#pragma once

#include <array>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/bounds.h"
#include "renderer/scene/light.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// Where a light's shadow map looks from: the view-projection of every layer it renders, in the
// reversed-depth [0,1] convention of the rest of the renderer (nearer = larger depth).
//
// Point lights: six cube faces (cubeFaceView/cubeFaceProjection). Spot lights: one square
// perspective around the outer cone. Directional lights: one orthographic map per cascade,
// fitted to the part of the camera's view (split by view depth) that holds scene geometry.

// Widest half angle a spot light's single perspective map covers; cone parts beyond it are lit.
inline constexpr float kMaxSpotShadowHalfAngle = 1.4835298641951802f;  // 85 degrees

struct SpotShadowFrame {
  glm::mat4 viewProjection{1.0f};
  float tanHalfFov = 1.0f;   // texel world size = 2 * viewDepth * tanHalfFov / resolution
  bool coneClipped = false;  // the outer cone is wider than kMaxSpotShadowHalfAngle
};

// The spot map's frustum holds the outer cone plus a margin of two texels for filters.
SpotShadowFrame spotShadowFrame(const Light& light, float near, float far, int resolution);

struct Cascade {
  glm::mat4 viewProjection{1.0f};
  float viewDepthEnd = 0.0f;  // camera view depth where this cascade ends
  float texelSize = 0.0f;     // world size of one texel (the larger side)
};

struct DirectionalShadowFrame {
  std::vector<Cascade> cascades;
  // Distance along the light direction covered by the maps: depth 1 = nearToLight, 0 = far.
  float nearToLight = 0.0f;
  float farFromLight = 1.0f;
};

// View depths where cascades end: practical split of [near, far] mixing the logarithmic split
// (weight lambda) with the linear one. Returns `count` values, the last one `far`.
std::vector<float> cascadeSplits(float near, float far, int count, float lambda);

// Orthographic maps for a directional light: the light-space xy extent of each cascade is the
// camera's view slice intersected with the scene bounds; depth covers the whole scene so casters
// outside the slice still shadow it. Shadows end at light.shadow.distance (0 = the farthest
// scene point from the camera).
DirectionalShadowFrame directionalShadowFrame(const Light& light, const ViewCamera& camera,
                                              const Bounds& sceneBounds);

// A camera that sees what one layer of a spot or directional light's map sees (--light-views):
// `viewProjection` of that layer split into a view from the map's near plane along the light
// and the projection that remains, size x size pixels, rows in GL order like the map.
ViewCamera planarLightCamera(const Light& light, const glm::mat4& viewProjection, float near,
                             float far, int size);

// Off-center orthographic projection with reversed depth: view-space z = -near maps to 1,
// -far to 0.
glm::mat4 reversedOrthographicBox(float left, float right, float bottom, float top, float near,
                                  float far);

}  // namespace omnishadow
