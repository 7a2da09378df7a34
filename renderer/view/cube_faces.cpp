#include "renderer/view/cube_faces.h"

#include <cmath>

namespace omnishadow {

CubeLookup cubeLookup(const glm::vec3& d) {
  const glm::vec3 a = glm::abs(d);
  // Ties go to X, then Y, as Mesa and the reference implementations do.
  CubeFace face;
  float sc, tc, ma;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x >= 0 ? CubeFace::PosX : CubeFace::NegX;
    sc = d.x >= 0 ? -d.z : d.z;
    tc = -d.y;
    ma = a.x;
  } else if (a.y >= a.z) {
    face = d.y >= 0 ? CubeFace::PosY : CubeFace::NegY;
    sc = d.x;
    tc = d.y >= 0 ? d.z : -d.z;
    ma = a.y;
  } else {
    face = d.z >= 0 ? CubeFace::PosZ : CubeFace::NegZ;
    sc = d.z >= 0 ? d.x : -d.x;
    tc = -d.y;
    ma = a.z;
  }
  return {face, glm::vec2(sc / ma + 1.0f, tc / ma + 1.0f) * 0.5f};
}

glm::mat4 cubeFaceView(CubeFace face, const glm::vec3& center) {
  // Rows of the rotation: view x = sc, view y = tc, view -z = ma, from the table above.
  static const glm::vec3 kAxes[kCubeFaceCount][3] = {
      // right (s)          up (t)              forward (major axis)
      {{0, 0, -1}, {0, -1, 0}, {1, 0, 0}},   // +X
      {{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}},   // -X
      {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}},     // +Y
      {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},   // -Y
      {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}},    // +Z
      {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}},  // -Z
  };
  const auto& [right, up, forward] = kAxes[static_cast<int>(face)];
  glm::mat4 view(1.0f);
  for (int i = 0; i < 3; ++i) {
    view[i][0] = right[i];
    view[i][1] = up[i];
    view[i][2] = -forward[i];
  }
  view[3] =
      glm::vec4(-glm::dot(right, center), -glm::dot(up, center), glm::dot(forward, center), 1.0f);
  return view;
}

glm::mat4 cubeFaceProjection(float near, float far) {
  // clip.w = -z_eye; depth = clip.z / clip.w = near (far - z) / (z (far - near)), z = -z_eye.
  glm::mat4 p(0.0f);
  p[0][0] = 1.0f;
  p[1][1] = 1.0f;
  p[2][2] = near / (far - near);
  p[2][3] = -1.0f;
  p[3][2] = far * near / (far - near);
  return p;
}

float cubeDepthToAxisDistance(float depth, float near, float far) {
  return near * far / (depth * (far - near) + near);
}

float axisDistanceToCubeDepth(float z, float near, float far) {
  return near * (far - z) / (z * (far - near));
}

}  // namespace omnishadow
