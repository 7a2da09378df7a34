#include "renderer/render/antialiasing.h"

#include <string>

#include "renderer/core/errors.h"

namespace omnishadow {
namespace {

// Sixteenths of a pixel from the pixel center.
constexpr int kSamples4[][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
constexpr int kSamples8[][2] = {{1, -3}, {-1, 3},  {5, 1}, {-3, -5},
                                {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
constexpr int kSamples16[][2] = {{1, 1},  {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5},
                                 {5, 3},  {3, -5},  {-2, 6}, {0, -7}, {-4, -6}, {-6, 4},
                                 {-8, 0}, {7, -4},  {6, 7},  {-7, -8}};

template <std::size_t N>
std::vector<glm::vec2> offsets(const int (&pattern)[N][2]) {
  std::vector<glm::vec2> out;
  for (const auto& p : pattern)
    out.emplace_back(static_cast<float>(p[0]) / 16.0f, static_cast<float>(p[1]) / 16.0f);
  return out;
}

}  // namespace

bool isAntialiasingSampleCount(int samples) {
  return samples == 1 || samples == 4 || samples == 8 || samples == 16;
}

void checkAntialiasingSampleCount(int samples) {
  if (!isAntialiasingSampleCount(samples))
    throw InputError("--aa " + std::to_string(samples) + ": expected 1, 4, 8 or 16");
}

std::vector<glm::vec2> antialiasingOffsets(int samples) {
  switch (samples) {
    case 4:
      return offsets(kSamples4);
    case 8:
      return offsets(kSamples8);
    case 16:
      return offsets(kSamples16);
    default:
      return {glm::vec2(0.0f)};
  }
}

ViewCamera jitteredCamera(const ViewCamera& camera, glm::vec2 offset) {
  // Sampling at center + offset means moving the image by -offset: in NDC a pixel is 2/size
  // wide, and NDC y runs up while image rows run down (unless read back in GL row order).
  const float ySign = camera.glRowOrder ? -1.0f : 1.0f;
  glm::mat4 shift(1.0f);
  shift[3][0] = -offset.x * 2.0f / static_cast<float>(camera.width);
  shift[3][1] = ySign * offset.y * 2.0f / static_cast<float>(camera.height);
  ViewCamera out = camera;
  out.projection = shift * camera.projection;
  return out;
}

}  // namespace omnishadow
