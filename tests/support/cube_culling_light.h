#pragma once

#include <glm/glm.hpp>

#include "renderer/view/caster_culling.h"
#include "renderer/view/cube_faces.h"

namespace omnishadow::test {

// A point light's culling description at `position`, with the six cube faces the shadow plan
// gives it for this depth range.
inline ShadowCullingLight cubeCullingLight(const glm::vec3& position, CullFace cullFace, float near,
                                           float far) {
  ShadowCullingLight light;
  light.type = LightType::Point;
  light.position = position;
  light.cullFace = cullFace;
  light.near = near;
  light.far = far;
  light.tanHalfFov = 1.0f;
  const glm::mat4 projection = cubeFaceProjection(near, far);
  for (int face = 0; face < kCubeFaceCount; ++face)
    light.viewProjections.push_back(projection *
                                    cubeFaceView(static_cast<CubeFace>(face), position));
  return light;
}

}  // namespace omnishadow::test
