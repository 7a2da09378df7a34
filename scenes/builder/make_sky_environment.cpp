// Writes scenes/environments/sky.exr: an equirectangular environment (lights file
// "environment") of a clear sky over grey ground with a sun, for the demo and the examples.
// Analytic, not measured: a zenith-to-horizon gradient, a brighter band round the sun, and a
// sun disc of 0.6 degrees whose irradiance on a surface facing it is 3 (a white Lambertian
// surface facing it then shows about 1). Regenerate with scripts/make-sky-environment.sh.
#include <cmath>
#include <cstdio>
#include <exception>
#include <glm/glm.hpp>

#include "renderer/output/image_writer.h"
#include "renderer/view/environment_map.h"

namespace {

constexpr int kWidth = 512, kHeight = 256;
constexpr float kPi = 3.14159265358979f;

glm::vec3 skyRadiance(const glm::vec3& direction, const glm::vec3& sun) {
  const glm::vec3 zenith(0.18f, 0.32f, 0.75f), horizon(0.75f, 0.82f, 0.95f);
  const glm::vec3 ground(0.18f, 0.17f, 0.16f);
  const float up = direction.y;
  if (up < 0.0f) return glm::mix(horizon * 0.35f, ground, std::min(1.0f, -up * 8.0f));
  glm::vec3 sky = glm::mix(horizon, zenith, std::pow(up, 0.45f));
  // Forward scattering round the sun.
  const float towardsSun = std::max(glm::dot(direction, sun), 0.0f);
  sky += glm::vec3(1.0f, 0.85f, 0.6f) * (0.6f * std::pow(towardsSun, 24.0f));
  return sky;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_sky_environment OUT.exr\n");
    return 2;
  }
  try {
    const glm::vec3 sun = glm::normalize(glm::vec3(0.6f, 0.55f, 0.45f));
    const float sunRadius = 0.3f * kPi / 180.0f;  // angular
    const float sunSolidAngle = kPi * sunRadius * sunRadius;
    const glm::vec3 sunRadiance = glm::vec3(1.0f, 0.93f, 0.82f) * (3.0f / sunSolidAngle);
    omnishadow::FloatImage image;
    image.width = kWidth;
    image.height = kHeight;
    image.channels = {"R", "G", "B"};
    image.pixels.resize(static_cast<std::size_t>(kWidth) * kHeight * 3);
    // Each texel averages 4 x 4 directions, so that the sun, smaller than a texel, keeps its
    // energy in the texels it covers.
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        glm::vec3 sum(0.0f);
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) {
            const glm::vec2 uv(
                (static_cast<float>(x) + (static_cast<float>(i) + 0.5f) / 4.0f) / kWidth,
                (static_cast<float>(y) + (static_cast<float>(j) + 0.5f) / 4.0f) / kHeight);
            const glm::vec3 d = omnishadow::equirectDirection(uv);
            sum += skyRadiance(d, sun);
          }
        glm::vec3 value = sum / 16.0f;
        // The sun's energy into the texel whose centre is nearest it.
        const glm::vec2 sunUv = omnishadow::equirectCoordinates(sun);
        const int sunX = static_cast<int>(sunUv.x * kWidth),
                  sunY = static_cast<int>(sunUv.y * kHeight);
        if (x == sunX && y == sunY) {
          const float theta = (static_cast<float>(y) + 0.5f) / kHeight * kPi;
          const float texelSolidAngle = (2.0f * kPi / kWidth) * (kPi / kHeight) * std::sin(theta);
          value += sunRadiance * (sunSolidAngle / texelSolidAngle);
        }
        for (int c = 0; c < 3; ++c) image.at(x, y, c) = value[c];
      }
    omnishadow::writeExr(argv[1], image, omnishadow::ExrPixelType::Half);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "make_sky_environment: %s\n", error.what());
    return 1;
  }
  return 0;
}
