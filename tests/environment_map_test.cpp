// The CPU prefilter of equirectangular environment maps (renderer/view/environment_map.h)
// against the integrals it stands for, each computed here the slow way: over every texel of
// the environment, or over a fine grid of the hemisphere. No GL.
#include "renderer/view/environment_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

namespace omnishadow::environment_map_test {
namespace {

constexpr double kPi = std::numbers::pi;

// The direction of polar angle theta (from +Y) and azimuth phi (from -Z toward +X).
glm::dvec3 sphericalDirection(double theta, double phi) {
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

// The direction through the centre of texel (x, y) of a width x height panorama.
glm::dvec3 texelDirection(int x, int y, int width, int height) {
  return sphericalDirection((y + 0.5) * kPi / height, ((x + 0.5) / width - 0.5) * 2.0 * kPi);
}

// The solid angle of a texel of row y.
double texelSolidAngle(int y, int width, int height) {
  return 2.0 * kPi / width * (std::cos(y * kPi / height) - std::cos((y + 1) * kPi / height));
}

EquirectImage environment(int width, int height,
                          const std::function<glm::vec3(int x, int y)>& radiance) {
  EquirectImage image{width, height, std::vector<float>(std::size_t(width) * height * 3)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::vec3 value = radiance(x, y);
      for (int c = 0; c < 3; ++c) image.rgb[(std::size_t(y) * width + x) * 3 + c] = value[c];
    }
  return image;
}

glm::vec3 texel(const EquirectImage& image, int x, int y) {
  const float* rgb = &image.rgb[(std::size_t(y) * image.width + x) * 3];
  return {rgb[0], rgb[1], rgb[2]};
}

// Bilinear, wrapping around in u and clamped in v, as the lighting pass reads the images.
glm::vec3 bilinear(const EquirectImage& image, const glm::vec2& uv) {
  const double x = uv.x * image.width - 0.5, y = uv.y * image.height - 0.5;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const float fx = float(x - x0), fy = float(y - y0);
  const auto at = [&](int i, int j) {
    return texel(image, ((i % image.width) + image.width) % image.width,
                 std::clamp(j, 0, image.height - 1));
  };
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx),
                  glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

double ggx(double nDotH, double alpha) {
  const double a2 = alpha * alpha, d = nDotH * nDotH * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}

// The height-correlated Smith G over 4 n.l n.v (Heitz 2014), the split sum's visibility.
double smithVisibility(double nDotL, double nDotV, double alpha) {
  const double a2 = alpha * alpha;
  return 0.5 / (nDotL * std::sqrt(nDotV * nDotV * (1.0 - a2) + a2) +
                nDotV * std::sqrt(nDotL * nDotL * (1.0 - a2) + a2));
}

// The GGX-weighted mean of the radiance around r with N = V = r, over every texel:
// sum L max(r.l, 0) D(h) dOmega / sum max(r.l, 0) D(h) dOmega.
glm::dvec3 bruteForceSpecular(const EquirectImage& radiance, const glm::dvec3& r, double alpha) {
  glm::dvec3 sum(0.0);
  double weightSum = 0.0;
  for (int y = 0; y < radiance.height; ++y)
    for (int x = 0; x < radiance.width; ++x) {
      const glm::dvec3 l = texelDirection(x, y, radiance.width, radiance.height);
      const double nDotL = glm::dot(r, l);
      if (nDotL <= 0.0) continue;
      const double weight = nDotL * ggx(glm::dot(r, glm::normalize(r + l)), alpha) *
                            texelSolidAngle(y, radiance.width, radiance.height);
      sum += weight * glm::dvec3(texel(radiance, x, y));
      weightSum += weight;
    }
  return sum / weightSum;
}

void expectSameBytes(const EquirectImage& a, const EquirectImage& b, const char* what) {
  ASSERT_EQ(a.width, b.width) << what;
  ASSERT_EQ(a.height, b.height) << what;
  ASSERT_EQ(a.rgb.size(), b.rgb.size()) << what;
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0) << what;
}

TEST(EnvironmentMap, CoordinatesOfTheAxes) {
  const auto expectUv = [](const glm::vec3& d, float u, float v) {
    const glm::vec2 uv = equirectCoordinates(d);
    if (u >= 0.0f) {
      EXPECT_NEAR(uv.x, u, 1e-6f) << d.x << " " << d.y << " " << d.z;
    }
    EXPECT_NEAR(uv.y, v, 1e-6f) << d.x << " " << d.y << " " << d.z;
  };
  expectUv({0, 0, -1}, 0.5f, 0.5f);
  expectUv({1, 0, 0}, 0.75f, 0.5f);
  expectUv({-1, 0, 0}, 0.25f, 0.5f);
  expectUv({0, 3, 0}, -1.0f, 0.0f);   // either u: a pole
  expectUv({0, -2, 0}, -1.0f, 1.0f);  // and not normalized
  expectUv({0, 5, -5}, 0.5f, 0.25f);
  // +Z is the seam, at u = 0 or 1.
  const float seam = equirectCoordinates({0, 0, 1}).x;
  EXPECT_TRUE(std::abs(seam) < 1e-6f || std::abs(seam - 1.0f) < 1e-6f) << seam;

  const auto expectDirection = [](const glm::vec2& uv, const glm::vec3& d) {
    const glm::vec3 got = equirectDirection(uv);
    EXPECT_NEAR(glm::distance(got, d), 0.0f, 1e-6f) << uv.x << " " << uv.y;
  };
  expectDirection({0.5f, 0.5f}, {0, 0, -1});
  expectDirection({0.75f, 0.5f}, {1, 0, 0});
  expectDirection({0.0f, 0.5f}, {0, 0, 1});
  expectDirection({0.3f, 0.0f}, {0, 1, 0});
  expectDirection({0.3f, 1.0f}, {0, -1, 0});
}

TEST(EnvironmentMap, CoordinatesAndDirectionsRoundTrip) {
  std::mt19937 random(7);
  std::normal_distribution<float> normal;
  std::uniform_real_distribution<float> scale(0.01f, 100.0f), unit(0.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 d(normal(random), normal(random), normal(random));
    const glm::vec3 back = equirectDirection(equirectCoordinates(d * scale(random)));
    EXPECT_NEAR(glm::length(back), 1.0f, 1e-5f);
    EXPECT_LT(glm::distance(back, glm::normalize(d)), 1e-5f) << d.x << " " << d.y << " " << d.z;

    // Away from the poles, where u is not determined, and the seam, where it jumps.
    const glm::vec2 uv(0.001f + 0.998f * unit(random), 0.01f + 0.98f * unit(random));
    const glm::vec2 uvBack = equirectCoordinates(equirectDirection(uv));
    EXPECT_NEAR(uvBack.x, uv.x, 2e-5f);
    EXPECT_NEAR(uvBack.y, uv.y, 2e-5f);
  }
}

// Every filter the prefilter applies is a weighted mean: of a constant, the constant.
TEST(EnvironmentMap, ConstantEnvironmentStaysConstant) {
  const glm::vec3 constant(0.5f, 1.0f, 2.0f);
  for (const auto& [width, height] :
       {std::pair{64, 32}, std::pair{37, 19}, std::pair{2048, 1024}}) {
    const PrefilteredEnvironment prefiltered =
        prefilterEnvironment(environment(width, height, [&](int, int) { return constant; }), 2);
    std::vector<const EquirectImage*> images{&prefiltered.irradiance};
    for (const EquirectImage& level : prefiltered.specular) images.push_back(&level);
    for (std::size_t k = 0; k < images.size(); ++k) {
      const EquirectImage& image = *images[k];
      ASSERT_EQ(image.rgb.size(), std::size_t(image.width) * image.height * 3);
      for (std::size_t i = 0; i < image.rgb.size(); ++i)
        ASSERT_NEAR(image.rgb[i], constant[i % 3], 1e-4 * constant[i % 3])
            << width << " x " << height << ", " << (k == 0 ? "irradiance" : "specular level ")
            << (k == 0 ? 0 : k - 1) << ", texel " << i / 3;
    }
  }
}

// A uniform sky over a black ground: a normal at polar angle theta sees (1 + cos theta) / 2 of
// its cosine-weighted hemisphere lit.
TEST(EnvironmentMap, IrradianceOfASkyOverBlackGround) {
  const glm::vec3 sky(1.0f, 0.5f, 2.0f);
  const EquirectImage radiance = environment(256, 128, [&](int x, int y) {
    return texelDirection(x, y, 256, 128).y > 0.0 ? sky : glm::vec3(0.0f);
  });
  const EquirectImage& irradiance = prefilterEnvironment(radiance, 2).irradiance;
  ASSERT_EQ(irradiance.width, kIrradianceWidth);
  ASSERT_EQ(irradiance.height, kIrradianceWidth / 2);

  const auto expectFraction = [&](const glm::vec3& got, double fraction, double tolerance,
                                  const char* where) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], fraction * sky[c], tolerance * sky[c]) << where;
  };
  expectFraction(bilinear(irradiance, equirectCoordinates({0, 1, 0})), 1.0, 0.02, "up");
  expectFraction(bilinear(irradiance, equirectCoordinates({0, -1, 0})), 0.0, 0.01, "down");
  for (const glm::vec3& horizontal : {glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(-1, 0, 1)})
    expectFraction(bilinear(irradiance, equirectCoordinates(horizontal)), 0.5, 0.03, "horizon");

  for (int y = 0; y < irradiance.height; ++y)
    for (int x = 0; x < irradiance.width; ++x) {
      const double cosTheta = texelDirection(x, y, irradiance.width, irradiance.height).y;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(texel(irradiance, x, y)[c], 0.5 * (1.0 + cosTheta) * sky[c], 0.005 * sky[c])
            << "texel " << x << ", " << y;
    }
}

// Bright patches on a dim ground and a lit floor, 64 x 32: sharp edges and a contrast of 100,
// where the width and shape of a lobe show.
EquirectImage patchyEnvironment() {
  return environment(64, 32, [](int x, int y) {
    glm::vec3 value(0.05f, 0.08f, 0.1f);
    if (x >= 8 && x < 16 && y >= 4 && y < 10) value += glm::vec3(8.0f, 6.0f, 3.0f);
    if (x >= 30 && x < 34 && y >= 12 && y < 18) value += glm::vec3(2.0f, 10.0f, 4.0f);
    if (x >= 44 && x < 60 && y >= 20 && y < 24) value += glm::vec3(3.0f, 2.0f, 9.0f);
    if (y >= 28) value += glm::vec3(1.0f, 0.7f, 0.4f);
    return value;
  });
}

// Every texel of the irradiance against the cosine-weighted mean over every texel of the
// environment.
TEST(EnvironmentMap, IrradianceMatchesBruteForceCosineMean) {
  const EquirectImage radiance = patchyEnvironment();
  const EquirectImage& irradiance = prefilterEnvironment(radiance, 2).irradiance;
  for (int y = 0; y < irradiance.height; ++y)
    for (int x = 0; x < irradiance.width; ++x) {
      const glm::dvec3 n = texelDirection(x, y, irradiance.width, irradiance.height);
      glm::dvec3 sum(0.0);
      double weightSum = 0.0;
      for (int ty = 0; ty < radiance.height; ++ty)
        for (int tx = 0; tx < radiance.width; ++tx) {
          const double cosine =
              glm::dot(n, texelDirection(tx, ty, radiance.width, radiance.height));
          if (cosine <= 0.0) continue;
          const double weight = cosine * texelSolidAngle(ty, radiance.width, radiance.height);
          sum += weight * glm::dvec3(texel(radiance, tx, ty));
          weightSum += weight;
        }
      // The sum over all of a sphere's texels is pi, to within the grid's error.
      ASSERT_NEAR(weightSum, kPi, 0.01);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(texel(irradiance, x, y)[c], sum[c] / weightSum, 0.01 * sum[c] / weightSum)
            << "texel " << x << ", " << y << ", channel " << c;
    }
}

// A sky of 0.5 with a sun of 3 texels' width carrying a known irradiance: extractSun() finds its
// direction and its irradiance above the sky, and leaves the sky where it was.
TEST(EnvironmentMap, ExtractSunFindsTheSunAndLeavesTheSky) {
  constexpr int kWidth = 512, kHeight = 256;
  const glm::dvec3 sunDirection = glm::normalize(glm::dvec3(0.5, 0.7, -0.4));
  const glm::vec2 sunUv = equirectCoordinates(glm::vec3(sunDirection));
  const int sx = static_cast<int>(sunUv.x * kWidth), sy = static_cast<int>(sunUv.y * kHeight);
  const glm::vec3 sky(0.4f, 0.5f, 0.6f), sunRadiance(4000.0f, 3600.0f, 3000.0f);
  EquirectImage image = environment(kWidth, kHeight, [&](int x, int y) {
    return std::abs(x - sx) <= 1 && std::abs(y - sy) <= 1 ? sky + sunRadiance : sky;
  });
  glm::dvec3 expectedIrradiance(0.0), expectedDirection(0.0);
  for (int y = sy - 1; y <= sy + 1; ++y)
    for (int x = sx - 1; x <= sx + 1; ++x) {
      expectedIrradiance += glm::dvec3(sunRadiance) * texelSolidAngle(y, kWidth, kHeight);
      expectedDirection +=
          texelDirection(x, y, kWidth, kHeight) * texelSolidAngle(y, kWidth, kHeight);
    }
  const std::optional<EnvironmentSun> sun = extractSun(image);
  ASSERT_TRUE(sun);
  EXPECT_GT(glm::dot(glm::dvec3(sun->direction), glm::normalize(expectedDirection)),
            std::cos(0.1 * kPi / 180.0));
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(sun->irradiance[c], expectedIrradiance[c], 1e-3 * expectedIrradiance[c]);
  EXPECT_GT(sun->angularRadius, 0.0f);
  EXPECT_LT(sun->angularRadius, 1.5f * kPi / 180.0f);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    ASSERT_NEAR(image.rgb[i], sky[i % 3], 1e-6f) << "texel " << i / 3;

  // Nothing stands out of a uniform sky, nor of a gradient: no sun, the image untouched.
  EquirectImage gradient = environment(64, 32, [](int, int y) { return glm::vec3(1.0f + y); });
  const std::vector<float> before = gradient.rgb;
  EXPECT_FALSE(extractSun(gradient));
  EXPECT_EQ(gradient.rgb, before);
}

// Each texel of two rough levels against the GGX-weighted mean over every texel. A lobe of the
// wrong width (alpha = roughness rather than its square) is off by up to 66 percent here.
TEST(EnvironmentMap, SpecularLevelMatchesBruteForceGgx) {
  const EquirectImage radiance = patchyEnvironment();
  const PrefilteredEnvironment prefiltered = prefilterEnvironment(radiance, 2);
  ASSERT_EQ(prefiltered.specular.size(), 6u);
  for (const int k : {3, 5}) {  // roughness 0.6 and 1
    const EquirectImage& level = prefiltered.specular[k];
    const double roughness = k / 5.0, alpha = roughness * roughness;
    for (int y = 0; y < level.height; ++y)
      for (int x = 0; x < level.width; ++x) {
        const glm::dvec3 expected =
            bruteForceSpecular(radiance, texelDirection(x, y, level.width, level.height), alpha);
        const glm::vec3 got = texel(level, x, y);
        for (int c = 0; c < 3; ++c) {
          const double error = std::abs(got[c] - expected[c]) / expected[c];
          EXPECT_LT(error, 0.05) << "level " << k << ", texel " << x << ", " << y << ", channel "
                                 << c << ": " << got[c] << " against " << expected[c];
        }
      }
  }
}

TEST(EnvironmentMap, LevelsFormTheMipChainOfLevelZero) {
  // Wider than kMaxSpecularWidth: level 0 is its area average. Constant over the 4 x 4 blocks
  // that each texel of level 0 covers, it is that constant.
  const auto blockValue = [](int bx, int by) {
    return glm::vec3(float(bx % 7), float(by % 5), float((bx + by) % 3));
  };
  const PrefilteredEnvironment large = prefilterEnvironment(
      environment(4096, 2048, [&](int x, int y) { return blockValue(x / 4, y / 4); }), 2);
  ASSERT_EQ(large.specular.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(large.specular[k].width, 1024 >> k);
    EXPECT_EQ(large.specular[k].height, 512 >> k);
    EXPECT_EQ(large.specular[k].rgb.size(), std::size_t(1024 >> k) * (512 >> k) * 3);
  }
  for (int y = 0; y < 512; y += 17)
    for (int x = 0; x < 1024; x += 13)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(texel(large.specular[0], x, y)[c], blockValue(x, y)[c], 1e-5)
            << "texel " << x << ", " << y;

  // At most kMaxSpecularWidth wide: level 0 is the picture itself, and the chain as long as
  // its mips go (1 + log2(16) levels, roughness 0, 0.25, ..., 1), down to 1 x 1.
  std::mt19937 random(3);
  std::uniform_real_distribution<float> unit(0.0f, 4.0f);
  const EquirectImage small = environment(
      16, 8, [&](int, int) { return glm::vec3(unit(random), unit(random), unit(random)); });
  const PrefilteredEnvironment prefiltered = prefilterEnvironment(small, 1);
  ASSERT_EQ(prefiltered.specular.size(), 5u);
  const int sizes[5][2] = {{16, 8}, {8, 4}, {4, 2}, {2, 1}, {1, 1}};
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(prefiltered.specular[k].width, sizes[k][0]) << "level " << k;
    EXPECT_EQ(prefiltered.specular[k].height, sizes[k][1]) << "level " << k;
    EXPECT_EQ(prefiltered.specular[k].rgb.size(), std::size_t(sizes[k][0]) * sizes[k][1] * 3);
  }
  expectSameBytes(prefiltered.specular[0], small, "level 0");
  EXPECT_EQ(prefiltered.irradiance.width, kIrradianceWidth);
  EXPECT_EQ(prefiltered.irradiance.height, kIrradianceWidth / 2);

  // Not 2:1, and a single texel: a single level, the picture.
  const EquirectImage odd = environment(300, 7, [](int, int) { return glm::vec3(1.0f); });
  EXPECT_EQ(prefilterEnvironment(odd, 1).specular.size(), 6u);
  EXPECT_EQ(prefilterEnvironment(odd, 1).specular[5].height, 1);
  const EquirectImage one =
      environment(1, 1, [](int, int) { return glm::vec3(0.25f, 0.5f, 1.0f); });
  const PrefilteredEnvironment single = prefilterEnvironment(one, 1);
  ASSERT_EQ(single.specular.size(), 1u);
  expectSameBytes(single.specular[0], one, "1 x 1 level 0");
  EXPECT_NEAR(single.irradiance.rgb[0], 0.25f, 1e-6f);
}

TEST(EnvironmentMap, SameBytesWhateverTheThreads) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> unit(0.0f, 10.0f);
  // Odd mip sizes on the way down, and one wider than kMaxSpecularWidth and not 2:1.
  for (const auto& [width, height] : {std::pair{96, 48}, std::pair{1500, 700}}) {
    const EquirectImage radiance = environment(width, height, [&](int, int) {
      return glm::vec3(unit(random), unit(random), unit(random));
    });
    const PrefilteredEnvironment one = prefilterEnvironment(radiance, 1);
    const PrefilteredEnvironment three = prefilterEnvironment(radiance, 3);
    ASSERT_EQ(one.specular.size(), three.specular.size());
    for (std::size_t k = 0; k < one.specular.size(); ++k)
      expectSameBytes(one.specular[k], three.specular[k], "specular level");
    expectSameBytes(one.irradiance, three.irradiance, "irradiance");
  }
}

TEST(EnvironmentMap, RejectsMalformedImages) {
  EXPECT_THROW(prefilterEnvironment(EquirectImage{}, 1), std::invalid_argument);
  EXPECT_THROW(prefilterEnvironment(EquirectImage{0, 4, {}}, 1), std::invalid_argument);
  EXPECT_THROW(prefilterEnvironment(EquirectImage{4, 2, std::vector<float>(23)}, 1),
               std::invalid_argument);
  EXPECT_THROW(prefilterEnvironment(EquirectImage{4, 2, std::vector<float>(25)}, 1),
               std::invalid_argument);
  EXPECT_THROW(prefilterEnvironment(EquirectImage{-4, -2, std::vector<float>(24)}, 1),
               std::invalid_argument);
  EXPECT_NO_THROW(prefilterEnvironment(EquirectImage{4, 2, std::vector<float>(24)}, 1));
}

// A mirror reflects everything: A + B = 1. And no entry reflects more than arrives.
TEST(EnvironmentMap, BrdfTableConservesEnergy) {
  const SpecularBrdfTable table = specularBrdfTable(32);
  ASSERT_EQ(table.size, 32);
  ASSERT_EQ(table.scaleBias.size(), 32u * 32u * 2u);
  for (int i = 0; i < 32; ++i)
    EXPECT_NEAR(table.scaleBias[i * 2] + table.scaleBias[i * 2 + 1], 1.0f, 0.02f)
        << "n.v column " << i;
  for (std::size_t e = 0; e < table.scaleBias.size(); e += 2) {
    const float scale = table.scaleBias[e], bias = table.scaleBias[e + 1];
    EXPECT_GE(scale, 0.0f) << e / 2;
    EXPECT_LE(scale, 1.0f) << e / 2;
    EXPECT_GE(bias, 0.0f) << e / 2;
    EXPECT_LE(bias, 1.0f) << e / 2;
    EXPECT_LE(scale + bias, 1.001f) << e / 2;
  }
  EXPECT_THROW(specularBrdfTable(0), std::invalid_argument);
}

// A and B as integrals over the hemisphere of l, by the midpoint rule on a 512 x 512 grid of
// (cos theta, phi) (uniform in solid angle), against the table's importance sampling.
TEST(EnvironmentMap, BrdfTableMatchesHemisphereIntegral) {
  constexpr int kSize = 16;
  const SpecularBrdfTable table = specularBrdfTable(kSize);
  for (const auto& [i, j] : {std::pair{1, 5}, std::pair{4, 8}, std::pair{8, 5}, std::pair{12, 11},
                             std::pair{15, 15}, std::pair{6, 14}}) {
    const double nDotV = (i + 0.5) / kSize, roughness = (j + 0.5) / kSize;
    ASSERT_GE(roughness, 0.3);
    const double alpha = roughness * roughness;
    const glm::dvec3 v(std::sqrt(1.0 - nDotV * nDotV), 0.0, nDotV);
    constexpr int kSteps = 512;
    double scale = 0.0, bias = 0.0;
    for (int a = 0; a < kSteps; ++a) {
      const double cosTheta = (a + 0.5) / kSteps, sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
      for (int b = 0; b < kSteps; ++b) {
        const double phi = (b + 0.5) * 2.0 * kPi / kSteps;
        const glm::dvec3 l(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
        const glm::dvec3 h = glm::normalize(v + l);
        const double f = std::pow(1.0 - glm::dot(v, h), 5.0);
        const double brdfCosine = ggx(h.z, alpha) * smithVisibility(l.z, nDotV, alpha) * l.z;
        scale += (1.0 - f) * brdfCosine;
        bias += f * brdfCosine;
      }
    }
    const double cell = (1.0 / kSteps) * (2.0 * kPi / kSteps);
    const float* entry = &table.scaleBias[(j * kSize + i) * 2];
    EXPECT_NEAR(entry[0], scale * cell, 0.01) << "n.v " << nDotV << ", roughness " << roughness;
    EXPECT_NEAR(entry[1], bias * cell, 0.01) << "n.v " << nDotV << ", roughness " << roughness;
  }
}

}  // namespace
}  // namespace omnishadow::environment_map_test
