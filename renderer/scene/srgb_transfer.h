#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace omnishadow {

// The sRGB transfer function (IEC 61966-2-1) of a linear value clamped to [0, 1].
float srgbEncode(float linear);

// round(255 * srgbEncode(linear)), from a table: NaN and values below 0 give 0, above 1 give 255.
std::uint8_t srgb8(float linear);

// round(255 * linear) of a value clamped to [0, 1]: the 8-bit code of a channel stored
// linearly (alpha, and textures that are not sRGB). NaN gives 0.
std::uint8_t linear8(float linear);

// linear8() of `count` values into `count` bytes, sixteen at a time.
void toLinear8(const float* values, std::size_t count, std::uint8_t* out);

// [k]: the least float whose srgb8() is k + 1; [255] is +infinity. srgb8() of a value in
// [0, 1] is the number of these it is at least.
const std::array<float, 256>& srgb8Steps();

// srgb8(linear[i * stride] * scale) into out[i * outStride] for i < count.
void toSrgb8(const float* linear, std::size_t count, std::size_t stride, float scale,
             std::uint8_t* out, std::size_t outStride);

// srgb8() of the R, G and B of `count` RGBA pixels times `scale`, into `count` RGB triples.
// The same bytes as toSrgb8() per channel, eight channels at a time where the CPU has AVX2.
void rgbaToSrgb8Rgb(const float* rgba, std::size_t count, float scale, std::uint8_t* rgb);

// The bytes of `count` RGBA texels whose R, G and B are sRGB-encoded and whose alpha is linear:
// srgb8() of R, G and B, and round(255 * A) of A in [0, 1] (the texels of a mipmap level).
void rgbaToSrgb8Rgba(const float* rgba, std::size_t count, std::uint8_t* out);

// The linear value of an 8-bit sRGB code.
float srgbDecode(std::uint8_t encoded);

}  // namespace omnishadow
