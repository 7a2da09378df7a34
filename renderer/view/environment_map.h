#pragma once

// Image-based lighting from an equirectangular environment map, prefiltered on the CPU for the
// split-sum approximation (Karis 2013): the specular radiance per roughness, the diffuse
// irradiance, and the table of the BRDF's scale and bias of F0. No GL.

#include <glm/glm.hpp>
#include <optional>
#include <vector>

namespace omnishadow {

// A latitude-longitude (equirectangular) picture of the light arriving from every direction:
// linear RGB radiance, row 0 at the top (+Y), the last row at the bottom (-Y). Its middle
// column looks along -Z, the column a quarter of the width to its right along +X (so that a
// camera looking down -Z, glTF's default, faces the middle of the panorama).
struct EquirectImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, row by row
};

// (u, v) in [0, 1]^2 of a direction (need not be normalized; nonzero):
// u = 0.5 + atan2(d.x, -d.z) / (2 pi), v = acos(clamp(d.y / |d|, -1, 1)) / pi.
glm::vec2 equirectCoordinates(const glm::vec3& direction);
// The unit direction of (u, v), the inverse of equirectCoordinates.
glm::vec3 equirectDirection(const glm::vec2& uv);

// The mean radiance over each texel of a width x height grid, by the solid angle each texel of
// `image` covers of it: up or down, any sizes.
EquirectImage resampleEquirect(const EquirectImage& image, int width, int height, int threads);
// The mips of `level0` below it, down to 1 x 1, each the area average of the one above (odd
// sizes too): with level 0, what a GL mipmapped texture of it holds.
std::vector<EquirectImage> equirectMips(const EquirectImage& level0, int threads);

// What the lighting pass reads of an environment (split-sum image-based lighting, Karis 2013).
struct PrefilteredEnvironment {
  // specular[k]: the radiance prefiltered with the GGX distribution at perceptual roughness
  // k / (specular.size() - 1) (alpha = roughness^2), with N = V = R. Level 0 is the radiance
  // itself (area-averaged down to at most kMaxSpecularWidth x kMaxSpecularWidth/2); level k is
  // max(1, width0 >> k) x max(1, height0 >> k): exactly a GL mipmap chain of level 0.
  std::vector<EquirectImage> specular;
  // E(n) / pi: the radiance a white Lambertian surface of normal n reflects (the cosine-weighted
  // mean of the radiance over the hemisphere around n), kIrradianceWidth x kIrradianceWidth/2.
  EquirectImage irradiance;
};
inline constexpr int kMaxSpecularWidth = 1024;
// Roughness 0, 0.2, ..., 1; fewer when level 0 is narrower than 32: min(kSpecularLevels,
// 1 + floor(log2(width0))) levels, as many as its mip chain has (a single one: roughness 0).
inline constexpr int kSpecularLevels = 6;
inline constexpr int kIrradianceWidth = 32;

// Throws std::invalid_argument when the image is empty or rgb.size() != width*height*3.
// Deterministic: the same bytes whatever `threads` (>= 1; less counts as 1) is.
PrefilteredEnvironment prefilterEnvironment(const EquirectImage& radiance, int threads);

// A sun found in an environment: a small region far brighter than the rest of the sky.
struct EnvironmentSun {
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // towards the sun, unit, in the image's frame
  glm::vec3 irradiance{0.0f};  // RGB: what it adds on a surface facing it, sum of L dOmega
  float angularRadius = 0.0f;  // radians: to the region's farthest texel centre
};

// Finds the sun of an environment and takes it out: the brightest texel's luminance must exceed
// kSunContrast x the mean over the sphere; the sun is every texel within kSunSearchRadians of
// it brighter than kSunThreshold x that texel's luminance, its irradiance what those texels
// hold above the sky around them (the mean of a ring just outside), to which they are set. The
// direction is weighted by that excess. nullopt (and the image untouched) when no texel stands
// out so (an overcast or indoor panorama). Throws std::invalid_argument for a malformed image.
inline constexpr float kSunContrast = 50.0f;
inline constexpr float kSunSearchRadians = 0.087266f;  // 5 degrees
inline constexpr float kSunThreshold = 0.02f;
std::optional<EnvironmentSun> extractSun(EquirectImage& radiance);

// The split-sum's scale A and bias B of F0 (specular = prefiltered * (F0 * A + F90 * B)) for
// the GGX BRDF with the height-correlated Smith visibility, at n.v = (i + 0.5) / size
// (columns i) and perceptual roughness (j + 0.5) / size (rows j): (A, B) pairs, row by row.
// Throws std::invalid_argument when size < 1.
struct SpecularBrdfTable {
  int size = 0;
  std::vector<float> scaleBias;  // size * size * 2
};
SpecularBrdfTable specularBrdfTable(int size);

}  // namespace omnishadow
