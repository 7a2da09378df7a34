#include "renderer/output/display_transform.h"

#include <cmath>

#include "renderer/scene/srgb_transfer.h"

namespace omnishadow {

std::vector<std::uint8_t> toSrgb8(const FloatImage& beauty, float exposure) {
  const float scale = std::exp2(exposure);
  const std::size_t count = static_cast<std::size_t>(beauty.width) * beauty.height;
  const std::size_t stride = beauty.channels.size();
  std::vector<std::uint8_t> out(count * 3);
  for (std::size_t c = 0; c < 3; ++c)
    toSrgb8(beauty.pixels.data() + c, count, stride, scale, out.data() + c, 3);
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
