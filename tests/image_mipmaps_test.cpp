#include "renderer/scene/image_mipmaps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "renderer/scene/srgb_transfer.h"

namespace omnishadow::image_mipmaps_test {
namespace {

Image filled(int width, int height, std::vector<std::uint8_t> rgba) {
  Image image;
  image.width = width;
  image.height = height;
  image.rgba = std::move(rgba);
  return image;
}

Image uniform(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b,
              std::uint8_t a) {
  std::vector<std::uint8_t> rgba;
  for (int i = 0; i < width * height; ++i) rgba.insert(rgba.end(), {r, g, b, a});
  return filled(width, height, rgba);
}

TEST(ImageMipmaps, LevelsAreSizedAsGlGenerateMipmapSizesThemDownToOneByOne) {
  const std::vector<Image> chain = mipmapChain(uniform(13, 4, 0, 0, 0, 255), true);
  const std::vector<std::pair<int, int>> expected = {{6, 2}, {3, 1}, {1, 1}};
  ASSERT_EQ(chain.size(), expected.size());
  for (std::size_t i = 0; i < chain.size(); ++i) {
    EXPECT_EQ(chain[i].width, expected[i].first);
    EXPECT_EQ(chain[i].height, expected[i].second);
    EXPECT_EQ(chain[i].rgba.size(), static_cast<std::size_t>(chain[i].width * chain[i].height * 4));
  }
  EXPECT_TRUE(mipmapChain(uniform(1, 1, 9, 9, 9, 9), false).empty());
}

TEST(ImageMipmaps, AUniformImageStaysExactlyTheSameAtEveryLevel) {
  for (bool srgb : {false, true})
    for (const Image& level : mipmapChain(uniform(37, 10, 17, 128, 250, 77), srgb))
      for (std::size_t i = 0; i < level.rgba.size(); i += 4) {
        ASSERT_EQ(level.rgba[i], 17);
        ASSERT_EQ(level.rgba[i + 1], 128);
        ASSERT_EQ(level.rgba[i + 2], 250);
        ASSERT_EQ(level.rgba[i + 3], 77);
      }
}

TEST(ImageMipmaps, SrgbColorsAreAveragedInLinearLightAndAlphaAndLinearImagesAsCodes) {
  // A 2x2 checker of black and white, alpha 0 and 255.
  const Image checker = filled(2, 2,
                               {0, 0, 0, 0, 255, 255, 255, 255,  //
                                255, 255, 255, 255, 0, 0, 0, 0});
  const Image srgb = mipmapChain(checker, true).at(0);
  ASSERT_EQ(srgb.width, 1);
  EXPECT_EQ(srgb.rgba[0], srgb8(0.5f));  // 188: half the light, not half the code
  EXPECT_EQ(srgb.rgba[0], 188);
  EXPECT_EQ(srgb.rgba[3], 128);  // alpha is linear: 127.5 rounds up
  const Image linear = mipmapChain(checker, false).at(0);
  EXPECT_EQ(linear.rgba[0], 128);
  EXPECT_EQ(linear.rgba[3], 128);
}

TEST(ImageMipmaps, EvenSidesTakeTheTwoByTwoBoxAndOddSidesTheAreaEachTexelCovers) {
  // 4x2 linear ramp in R: each level-1 texel is the mean of its 2x2 block.
  const Image ramp = filled(4, 2, {0,  0, 0, 0, 40, 0, 0, 0, 80,  0, 0, 0, 120, 0, 0, 0,  //
                                   20, 0, 0, 0, 60, 0, 0, 0, 100, 0, 0, 0, 140, 0, 0, 0});
  const Image box = mipmapChain(ramp, false).at(0);
  ASSERT_EQ(box.width, 2);
  EXPECT_EQ(box.rgba[0], 30);   // (0 + 40 + 20 + 60) / 4
  EXPECT_EQ(box.rgba[4], 110);  // (80 + 120 + 100 + 140) / 4
  // 3x1 -> 1x1: the one texel covers all three, a third each.
  const Image three = filled(3, 1, {30, 0, 0, 255, 60, 0, 0, 255, 150, 0, 0, 255});
  const Image area = mipmapChain(three, false).at(0);
  ASSERT_EQ(area.width, 1);
  EXPECT_EQ(area.rgba[0], 80);  // (30 + 60 + 150) / 3
  EXPECT_EQ(area.rgba[3], 255);
  // 5x1 -> 2x1: each covers 2.5 texels: the first 0, 1 and half of 2.
  const Image five =
      filled(5, 1, {0, 0, 0, 0, 50, 0, 0, 0, 100, 0, 0, 0, 150, 0, 0, 0, 200, 0, 0, 0});
  const Image halves = mipmapChain(five, false).at(0);
  ASSERT_EQ(halves.width, 2);
  EXPECT_EQ(halves.rgba[0], 40);   // (0 + 50 + 0.5 * 100) / 2.5
  EXPECT_EQ(halves.rgba[4], 160);  // (0.5 * 100 + 150 + 200) / 2.5
}

// Level 1 of a large image is made on two threads, half the rows each: every texel of it is the
// 2x2 box of its four texels above, summed in the order the one-thread path sums them, and the
// levels below follow from it. Noise, so that a row taken from the wrong place shows.
TEST(ImageMipmaps, LevelOneOfALargeImageIsTheTwoByTwoBoxOfEveryTexelOnTwoThreads) {
  constexpr int kWidth = 1024, kHeight = 512;  // at the two-thread threshold, 512^2 texels
  std::vector<std::uint8_t> rgba(std::size_t{kWidth} * kHeight * 4);
  std::uint32_t state = 7;
  for (std::uint8_t& value : rgba) {
    state = state * 1664525u + 1013904223u;
    value = static_cast<std::uint8_t>(state >> 24);
  }
  const Image image = filled(kWidth, kHeight, rgba);
  for (bool srgb : {true, false}) {
    SCOPED_TRACE(srgb ? "sRGB" : "linear");
    const std::vector<Image> chain = mipmapChain(image, srgb);
    ASSERT_EQ(chain.size(), 10u);  // 512x256 down to 1x1
    const Image& one = chain[0];
    ASSERT_EQ(one.width, kWidth / 2);
    ASSERT_EQ(one.height, kHeight / 2);
    std::size_t wrong = 0;
    for (int y = 0; y < one.height; ++y)
      for (int x = 0; x < one.width; ++x)
        for (int c = 0; c < 4; ++c) {
          const auto above = [&](int dx, int dy) {
            const std::uint8_t code =
                rgba[((std::size_t(2 * y + dy) * kWidth) + std::size_t(2 * x + dx)) * 4 + c];
            return srgb && c < 3 ? srgbDecode(code) : static_cast<float>(code) / 255.0f;
          };
          const float mean = 0.25f * ((above(0, 0) + above(1, 0)) + (above(0, 1) + above(1, 1)));
          const std::uint8_t expected =
              srgb && c < 3
                  ? srgb8(mean)
                  : static_cast<std::uint8_t>(std::clamp(mean, 0.0f, 1.0f) * 255.0f + 0.5f);
          wrong += one.rgba[(std::size_t(y) * one.width + x) * 4 + c] != expected;
        }
    EXPECT_EQ(wrong, 0u);
    // Level 2 comes from level 1's unrounded values, each within half a code of its code.
    if (!srgb) {
      const Image& two = chain[1];
      const int row = one.width * 4;
      EXPECT_NEAR(two.rgba[0],
                  (one.rgba[0] + one.rgba[4] + one.rgba[row] + one.rgba[row + 4]) / 4.0, 1.0);
    }
  }
}

// Level 2 of an image whose sides divide by 4 is made from level 1's rows while they are made,
// without holding level 1's linear values whole. It, and every level below whose level above
// has even sides, must still be the 2x2 box of the unrounded level above, rounded once, on one
// thread or two, also where a level's sides are odd.
TEST(ImageMipmaps, EvenLevelsAreBoxesOfTheUnroundedLevelAboveWhenMadeRowsAtATime) {
  for (const auto& [width, height] :
       {std::pair{1028, 516}, std::pair{64, 32}, std::pair{8, 12}, std::pair{4, 4}}) {
    std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4);
    std::uint32_t state = static_cast<std::uint32_t>(width * 31 + height);
    for (std::uint8_t& value : rgba) {
      state = state * 1664525u + 1013904223u;
      value = static_cast<std::uint8_t>(state >> 24);
    }
    const Image image = filled(width, height, rgba);
    for (bool srgb : {true, false}) {
      const std::vector<Image> chain = mipmapChain(image, srgb);
      // Each level in linear values, whole, from the one above while its sides are even.
      std::vector<float> above(rgba.size());
      for (std::size_t i = 0; i < rgba.size(); ++i)
        above[i] = srgb && i % 4 < 3 ? srgbDecode(rgba[i]) : static_cast<float>(rgba[i]) / 255.0f;
      int w = width, h = height;
      for (std::size_t level = 0; w % 2 == 0 && h % 2 == 0; ++level) {
        SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) +
                     (srgb ? " sRGB" : " linear") + ", level " + std::to_string(level + 1));
        const int w2 = w / 2, h2 = h / 2;
        std::vector<float> below(std::size_t(w2) * h2 * 4);
        for (int y = 0; y < h2; ++y)
          for (int x = 0; x < w2; ++x)
            for (int c = 0; c < 4; ++c) {
              const auto at = [&](int dx, int dy) {
                return above[((std::size_t(2 * y + dy) * w) + std::size_t(2 * x + dx)) * 4 + c];
              };
              below[(std::size_t(y) * w2 + x) * 4 + c] =
                  0.25f * ((at(0, 0) + at(1, 0)) + (at(0, 1) + at(1, 1)));
            }
        ASSERT_LT(level, chain.size());
        ASSERT_EQ(chain[level].width, w2);
        ASSERT_EQ(chain[level].height, h2);
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < below.size(); ++i) {
          const bool colour = srgb && i % 4 < 3;
          const std::uint8_t expected =
              colour ? srgb8(below[i])
                     : static_cast<std::uint8_t>(std::clamp(below[i], 0.0f, 1.0f) * 255.0f + 0.5f);
          wrong += chain[level].rgba[i] != expected;
        }
        EXPECT_EQ(wrong, 0u);
        above = std::move(below);
        w = w2;
        h = h2;
      }
    }
  }
}

}  // namespace
}  // namespace omnishadow::image_mipmaps_test
