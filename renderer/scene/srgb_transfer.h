#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace omnishadow {

// The sRGB transfer function (IEC 61966-2-1) of a linear value clamped to [0, 1].
float srgbEncode(float linear);

// round(255 * srgbEncode(linear)), from a table: NaN and values below 0 give 0, above 1 give 255.
std::uint8_t srgb8(float linear);

// [k]: the least float whose srgb8() is k + 1; [255] is +infinity. srgb8() of a value in
// [0, 1] is the number of these it is at least.
const std::array<float, 256>& srgb8Steps();

// srgb8(linear[i * stride] * scale) into out[i * outStride] for i < count.
void toSrgb8(const float* linear, std::size_t count, std::size_t stride, float scale,
             std::uint8_t* out, std::size_t outStride);

// The linear value of an 8-bit sRGB code.
float srgbDecode(std::uint8_t encoded);

}  // namespace omnishadow
