#pragma once

#include <cstdint>
#include <vector>

#include "renderer/output/image_writer.h"

namespace omnishadow {

// Linear premultiplied RGBA -> 8-bit sRGB RGB for PNG: scaled by 2^exposure, clamped to [0,1],
// encoded with the sRGB transfer function, rounded to nearest. Uncovered pixels stay black.
std::vector<std::uint8_t> toSrgb8(const FloatImage& beauty, float exposure);

// Same channels with RGB scaled by 2^exposure (alpha untouched), for EXR beauty output.
FloatImage applyExposure(const FloatImage& beauty, float exposure);

}  // namespace omnishadow
