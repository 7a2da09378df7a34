#include "renderer/output/display_transform.h"

#include <algorithm>
#include <cmath>

namespace omnishadow {

float srgbEncode(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

std::vector<std::uint8_t> toSrgb8(const FloatImage& beauty, float exposure) {
  const float scale = std::exp2(exposure);
  const std::size_t count = static_cast<std::size_t>(beauty.width) * beauty.height;
  const std::size_t stride = beauty.channels.size();
  std::vector<std::uint8_t> out(count * 3);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t c = 0; c < 3; ++c) {
      const float v = srgbEncode(beauty.pixels[i * stride + c] * scale);
      out[i * 3 + c] = static_cast<std::uint8_t>(std::lround(v * 255.0f));
    }
  }
  return out;
}

FloatImage applyExposure(const FloatImage& beauty, float exposure) {
  FloatImage out = beauty;
  const float scale = std::exp2(exposure);
  const std::size_t stride = out.channels.size();
  for (std::size_t i = 0; i < out.pixels.size(); ++i)
    if (i % stride < 3) out.pixels[i] *= scale;
  return out;
}

}  // namespace omnishadow
