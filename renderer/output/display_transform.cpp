#include "renderer/output/display_transform.h"

#include <cmath>
#include <cstddef>

#include "renderer/core/two_halves.h"
#include "renderer/scene/srgb_transfer.h"

namespace omnishadow {

namespace {

// From this many pixels on, two threads share the conversion: a 1280x720 frame took 5 ms on
// one, 2.7 on two (a micro-benchmark); the threads' start costs more than a small image takes.
constexpr std::size_t kTwoThreadPixels = std::size_t{1} << 18;

}  // namespace

std::vector<std::uint8_t> toSrgb8(const FloatImage& beauty, float exposure) {
  const float scale = std::exp2(exposure);
  const std::size_t count = static_cast<std::size_t>(beauty.width) * beauty.height;
  const std::size_t stride = beauty.channels.size();
  std::vector<std::uint8_t> out(count * 3);
  const auto pixels = [&](std::size_t first, std::size_t end) {
    if (stride == 4) {
      rgbaToSrgb8Rgb(beauty.pixels.data() + first * 4, end - first, scale, out.data() + first * 3);
      return;
    }
    for (std::size_t c = 0; c < 3; ++c)
      toSrgb8(beauty.pixels.data() + first * stride + c, end - first, stride, scale,
              out.data() + first * 3 + c, 3);
  };
  inTwoHalves(count, count >= kTwoThreadPixels, pixels);
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
