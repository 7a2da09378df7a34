#pragma once

#include <array>
#include <glm/glm.hpp>

namespace omnishadow {

// Cube map faces in GL order: GL_TEXTURE_CUBE_MAP_POSITIVE_X + face.
enum class CubeFace { PosX = 0, NegX, PosY, NegY, PosZ, NegZ };
inline constexpr int kCubeFaceCount = 6;
inline constexpr std::array<const char*, kCubeFaceCount> kCubeFaceNames = {"px", "nx", "py",
                                                                           "ny", "pz", "nz"};

// Where a direction lands in a cube map, by the selection rule of the GL specification
// (OpenGL 4.5 core, section 8.13, table 8.19): the major axis picks the face, and (s, t) in
// [0,1] are the texture coordinates on it; texel column = s * size, row = t * size (row 0 is
// the first row in memory).
struct CubeLookup {
  CubeFace face;
  glm::vec2 st;
};
CubeLookup cubeLookup(const glm::vec3& direction);

// World-to-face view matrix for a cube map centered at `center`. Together with
// cubeFaceProjection() it maps a point to clip space so that its NDC (x, y) is (2s-1, 2t-1) of
// cubeLookup(point - center): rendering with it into face `face` of a cube map (window y = t)
// puts every point exactly where sampling the cube map in its direction reads.
glm::mat4 cubeFaceView(CubeFace face, const glm::vec3& center);

// 90 degree square perspective with reversed depth for a [0,1] clip range (glClipControl
// GL_ZERO_TO_ONE): distance `near` along the face axis maps to depth 1, `far` to depth 0.
glm::mat4 cubeFaceProjection(float near, float far);

// Inverse of the depth mapping above: distance along the face's axis for a stored depth.
float cubeDepthToAxisDistance(float depth, float near, float far);
float axisDistanceToCubeDepth(float axisDistance, float near, float far);

}  // namespace omnishadow
