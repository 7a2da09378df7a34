#include "renderer/scene/srgb_transfer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "renderer/output/display_transform.h"

namespace omnishadow::srgb_transfer_test {
namespace {

// What srgb8() replaced: the transfer function and a rounding per channel.
int reference(float linear) {
  return static_cast<int>(std::lround(srgbEncode(linear) * 255.0f));
}

float fromBits(std::uint32_t bits) {
  return std::bit_cast<float>(bits);
}

TEST(SrgbTransfer, TheTableGivesTheTransferFunctionsByteOverADenseSampleOfZeroToOne) {
  const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
  int mismatches = 0;
  for (std::uint32_t bits = 0; bits <= one; bits += 251)
    if (srgb8(fromBits(bits)) != reference(fromBits(bits))) ++mismatches;
  EXPECT_EQ(mismatches, 0);
}

TEST(SrgbTransfer, TheTableGivesTheTransferFunctionsByteOnBothSidesOfEveryStep) {
  // Each of the 255 floats where the byte steps up, found by bisection here, and 4 ulps on
  // either side of it.
  for (int k = 1; k < 256; ++k) {
    std::uint32_t low = 0, high = std::bit_cast<std::uint32_t>(1.0f);
    while (high - low > 1) {
      const std::uint32_t middle = low + (high - low) / 2;
      (reference(fromBits(middle)) >= k ? high : low) = middle;
    }
    for (std::uint32_t bits = high - 4; bits <= high + 4; ++bits)
      ASSERT_EQ(srgb8(fromBits(bits)), reference(fromBits(bits)))
          << "step " << k << " bits " << bits;
    EXPECT_EQ(srgb8(fromBits(high)), k);
    EXPECT_EQ(srgb8(fromBits(high - 1)), k - 1);
  }
}

TEST(SrgbTransfer, ValuesOutsideZeroToOneClampAndNanIsBlack) {
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(srgb8(-0.0f), 0);
  EXPECT_EQ(srgb8(-1.0f), 0);
  EXPECT_EQ(srgb8(-inf), 0);
  EXPECT_EQ(srgb8(std::numeric_limits<float>::denorm_min()), 0);
  EXPECT_EQ(srgb8(1.0f), 255);
  EXPECT_EQ(srgb8(1e30f), 255);
  EXPECT_EQ(srgb8(inf), 255);
  EXPECT_EQ(srgb8(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(srgb8(0.5f), 188);  // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
  EXPECT_EQ(srgb8(0.001f), 3);  // linear segment: 12.92 * 0.001 * 255 = 3.29
}

TEST(SrgbTransfer, ToSrgb8ScalesByTheExposureBeforeEncodingAndDropsAlpha) {
  FloatImage image;
  image.width = 2;
  image.height = 1;
  image.channels = {"R", "G", "B", "A"};
  image.pixels = {0.25f, 0.5f, 2.0f, 0.5f, 0.0f, 0.125f, -1.0f, 1.0f};
  const std::vector<std::uint8_t> srgb = toSrgb8(image, 1.0f);
  const std::vector<std::uint8_t> expected = {
      static_cast<std::uint8_t>(reference(0.5f)),  255, 255, 0,
      static_cast<std::uint8_t>(reference(0.25f)), 0};
  EXPECT_EQ(srgb, expected);
}

// Large frames are converted on two threads, each half of the pixels: every byte is the one
// srgb8() gives its channel, on both sides of the split and at an odd pixel count.
TEST(SrgbTransfer, ToSrgb8OfALargeFrameIsEveryChannelsByteOnTwoThreads) {
  FloatImage image;
  image.width = 1281;
  image.height = 721;
  image.channels = {"R", "G", "B", "A"};
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * 4);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = static_cast<float>((i * 2654435761u) % 100003u) / 90000.0f;
  const std::vector<std::uint8_t> srgb = toSrgb8(image, -0.5f);
  ASSERT_EQ(srgb.size(), static_cast<std::size_t>(image.width) * image.height * 3);
  const float scale = std::exp2(-0.5f);
  std::size_t mismatches = 0;
  for (std::size_t p = 0; p < srgb.size() / 3; ++p)
    for (std::size_t c = 0; c < 3; ++c)
      if (srgb[3 * p + c] != srgb8(image.pixels[4 * p + c] * scale)) ++mismatches;
  EXPECT_EQ(mismatches, 0u);
}

// Every float from 0 to just above 1 in steps of 61 ulps, the floats on both sides of every
// step, and values outside [0, 1], as RGBA pixels (the alpha lanes take values too).
std::vector<float> denseRgba() {
  std::vector<float> values;
  const std::uint32_t above = std::bit_cast<std::uint32_t>(1.0f) + 64;
  for (std::uint32_t bits = 0; bits <= above; bits += 61) values.push_back(fromBits(bits));
  for (const float step : srgb8Steps()) {
    if (std::isinf(step)) continue;
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(step);
    for (std::uint32_t b = bits - 3; b <= bits + 3; ++b) values.push_back(fromBits(b));
  }
  const float inf = std::numeric_limits<float>::infinity();
  for (const float v :
       {-0.0f, -1.0f, -inf, inf, 1e30f, 2.0f, std::numeric_limits<float>::quiet_NaN(),
        std::numeric_limits<float>::denorm_min(), 1.0f})
    values.push_back(v);
  values.resize((values.size() + 3) / 4 * 4, 0.5f);                         // whole pixels
  if (values.size() / 4 % 2 == 0) values.resize(values.size() + 4, 0.25f);  // an odd count
  return values;
}

// The RGB conversion of whole pixels (eight channels at a time where the CPU has AVX2) gives
// srgb8() of each channel times the scale, at every count from 0 up, so the tail of an odd
// count is covered too.
TEST(SrgbTransfer, RgbaToSrgb8RgbIsEachChannelsSrgb8) {
  const std::vector<float> rgba = denseRgba();
  const std::size_t count = rgba.size() / 4;
  ASSERT_EQ(count % 2, 1u);
  for (const float scale : {1.0f, 0.70710677f, 4.0f}) {
    std::vector<std::uint8_t> rgb(count * 3 + 1, 77);
    rgbaToSrgb8Rgb(rgba.data(), count, scale, rgb.data());
    std::size_t mismatches = 0;
    for (std::size_t p = 0; p < count; ++p)
      for (std::size_t c = 0; c < 3; ++c)
        if (rgb[3 * p + c] != srgb8(rgba[4 * p + c] * scale)) ++mismatches;
    EXPECT_EQ(mismatches, 0u) << "scale " << scale;
    EXPECT_EQ(rgb.back(), 77) << "wrote past the last pixel";
  }
  for (std::size_t n = 0; n <= 17; ++n) {  // steps of eight pixels and what is left
    std::vector<std::uint8_t> rgb(n * 3 + 8, 77);
    rgbaToSrgb8Rgb(rgba.data(), n, 1.0f, rgb.data());
    for (std::size_t i = 0; i < n * 3; ++i)
      EXPECT_EQ(rgb[i], srgb8(rgba[i / 3 * 4 + i % 3])) << n << " pixels, byte " << i;
    for (std::size_t i = n * 3; i < rgb.size(); ++i) EXPECT_EQ(rgb[i], 77) << n << " pixels";
  }
}

// Runs of zero pixels (a frame's background), which the AVX2 path writes as zero bytes without
// converting them, of every length up to 20 at every offset in a step of eight, between pixels
// that are not zero, negative zeros among them: every byte still srgb8() of its channel, and
// written over what the output held.
TEST(SrgbTransfer, RgbaToSrgb8RgbWritesZeroRunsAsTheirBytes) {
  const std::vector<float> dense = denseRgba();
  ASSERT_GE(dense.size(), 4u * 40);
  for (std::size_t offset = 0; offset < 8; ++offset)
    for (std::size_t run = 1; run <= 20; ++run) {
      // Values near the steps (the dense sample's first ones all encode to 0).
      std::vector<float> rgba(dense.end() - 4 * 40, dense.end());
      for (std::size_t p = offset; p < offset + run; ++p)
        for (std::size_t c = 0; c < 4; ++c) rgba[4 * p + c] = 0.0f;
      rgba[4 * (offset + run) + 1] = -0.0f;  // the pixel after the run: not all zero bits
      const std::size_t count = rgba.size() / 4;
      std::vector<std::uint8_t> rgb(count * 3, 77);
      rgbaToSrgb8Rgb(rgba.data(), count, 2.0f, rgb.data());
      std::size_t mismatches = 0;
      for (std::size_t i = 0; i < count * 3; ++i)
        mismatches += rgb[i] != srgb8(rgba[i / 3 * 4 + i % 3] * 2.0f);
      EXPECT_EQ(mismatches, 0u) << "a run of " << run << " from pixel " << offset;
    }
}

// A mipmap level's texels: R, G and B as srgb8(), alpha rounded linearly.
TEST(SrgbTransfer, ToLinear8IsLinear8OfEachValue) {
  // A dense sample of [0, 1] with both sides of every rounding step (k + 0.5) / 255, then values
  // outside it, NaN and infinities.
  std::vector<float> values;
  const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
  for (std::uint32_t bits = 0; bits <= one; bits += 509) values.push_back(fromBits(bits));
  for (int k = 0; k < 255; ++k) {
    const float step = (static_cast<float>(k) + 0.5f) / 255.0f;
    for (float v = step, n = 0; n < 4; ++n) {
      values.push_back(v);
      v = std::nextafter(v, 0.0f);
    }
    for (float v = step, n = 0; n < 4; ++n) {
      values.push_back(v);
      v = std::nextafter(v, 2.0f);
    }
  }
  for (float v : {-0.0f, -1e-30f, -0.5f, 1.0f, 1.0000001f, 1.5f, 255.0f,
                  std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity()})
    values.push_back(v);
  std::vector<std::uint8_t> out(values.size() + 1, 77);
  toLinear8(values.data(), values.size(), out.data());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (out[i] != linear8(values[i])) ++mismatches;
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(out.back(), 77) << "wrote past the last value";
  EXPECT_EQ(linear8(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(linear8(0.5f), 128);         // 127.5 + 0.5
  EXPECT_EQ(linear8(2.0f / 510.0f), 1);  // 1 + 0.5, truncated
  // Every count from 0 to 40, so that each leaves a different tail after the blocks of 16.
  for (std::size_t count = 0; count <= 40; ++count) {
    std::vector<float> some(values.begin() + 1000, values.begin() + 1000 + count);
    std::vector<std::uint8_t> bytes(count + 1, 77);
    toLinear8(some.data(), count, bytes.data());
    for (std::size_t i = 0; i < count; ++i)
      ASSERT_EQ(bytes[i], linear8(some[i])) << "count " << count << ", value " << i;
    EXPECT_EQ(bytes[count], 77) << "count " << count;
  }
}

TEST(SrgbTransfer, RgbaToSrgb8RgbaEncodesColourAndRoundsAlphaLinearly) {
  std::vector<float> rgba = denseRgba();
  for (float& v : rgba)  // a level's values come from averaging decoded bytes: in [0, 1]
    if (!(v >= 0.0f && v <= 1.0f)) v = 0.0f;
  const std::size_t count = rgba.size() / 4;
  std::vector<std::uint8_t> out(count * 4 + 1, 77);
  rgbaToSrgb8Rgba(rgba.data(), count, out.data());
  std::size_t mismatches = 0;
  for (std::size_t p = 0; p < count; ++p) {
    for (std::size_t c = 0; c < 3; ++c)
      if (out[4 * p + c] != srgb8(rgba[4 * p + c])) ++mismatches;
    if (out[4 * p + 3] != static_cast<int>(std::lround(rgba[4 * p + 3] * 255.0f))) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(out.back(), 77) << "wrote past the last texel";
  const float alphas[] = {0.5f, 0.5f, 0.5f, 1.0f / 510.0f, 0.0f, 0.0f, 0.0f, 0.99f};
  std::uint8_t two[8] = {};
  rgbaToSrgb8Rgba(alphas, 2, two);
  EXPECT_EQ(two[3], 1);    // 0.5 + 0.5 rounds up
  EXPECT_EQ(two[7], 252);  // 252.45
  // A NaN alpha gives 0 as linear8() does, in the pairs of the vector path and the odd last
  // texel alike.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float three[12] = {0.5f, 0.5f, 0.5f, nan, 0.5f, 0.5f, 0.5f, 1.0f, 0.5f, 0.5f, 0.5f, nan};
  std::uint8_t codes[12] = {};
  rgbaToSrgb8Rgba(three, 3, codes);
  EXPECT_EQ(codes[3], 0);
  EXPECT_EQ(codes[7], 255);
  EXPECT_EQ(codes[11], 0);
}

}  // namespace
}  // namespace omnishadow::srgb_transfer_test
