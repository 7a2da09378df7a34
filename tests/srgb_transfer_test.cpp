#include "renderer/scene/srgb_transfer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "renderer/output/display_transform.h"

namespace omnishadow {
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

}  // namespace
}  // namespace omnishadow
