// compareImages and the heat map on small constructed images whose answers are known exactly.
#include "renderer/output/image_diff.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "renderer/core/errors.h"

namespace omnishadow::image_diff_test {
namespace {

// A width x height image with the given channels, every value `fill`.
FloatImage image(int width, int height, std::vector<std::string> channels, float fill = 0.25f) {
  FloatImage im;
  im.width = width;
  im.height = height;
  im.channels = std::move(channels);
  im.pixels.assign(static_cast<std::size_t>(width) * height * im.channels.size(), fill);
  return im;
}

// A gradient, so that equal images are not trivially constant.
FloatImage gradient(int width, int height, std::vector<std::string> channels) {
  FloatImage im = image(width, height, std::move(channels));
  for (std::size_t i = 0; i < im.pixels.size(); ++i)
    im.pixels[i] = static_cast<float>(i % 17) / 16.0f;
  return im;
}

TEST(ImageDiff, IdenticalImagesHaveZeroDifferenceAndInfinitePsnr) {
  const FloatImage a = gradient(7, 5, {"R", "G", "B", "A"});
  DiffOptions options;
  options.perChannel = true;
  const DiffResult r = compareImages(a, a, options);
  EXPECT_EQ(r.width, 7);
  EXPECT_EQ(r.height, 5);
  for (const DiffStats& s : {r.overall, r.perChannel[0], r.perChannel[3]}) {
    EXPECT_EQ(s.maxAbs, 0.0);
    EXPECT_EQ(s.meanAbs, 0.0);
    EXPECT_EQ(s.rmse, 0.0);
    EXPECT_TRUE(std::isinf(s.psnr) && s.psnr > 0);
    EXPECT_EQ(s.failingPixels, 0u);
    EXPECT_EQ(s.failingFraction, 0.0);
    EXPECT_EQ(s.maxX, -1);
    EXPECT_EQ(s.maxY, -1);
  }
  EXPECT_EQ(r.overall.channels, (std::vector<std::string>{"R", "G", "B", "A"}));
  ASSERT_EQ(r.perChannel.size(), 4u);
  EXPECT_EQ(r.perChannel[2].channels, std::vector<std::string>{"B"});
  EXPECT_EQ(r.pixelMaxAbs, std::vector<float>(35, 0.0f));
}

TEST(ImageDiff, OnePixelOffByHalf) {
  const int w = 8, h = 4, n = w * h;
  const FloatImage a = image(w, h, {"Y"});
  FloatImage b = a;
  b.at(5, 2, 0) += 0.5f;
  DiffOptions options;
  options.peak = 1.0;
  const DiffResult r = compareImages(a, b, options);
  EXPECT_EQ(r.overall.maxAbs, 0.5);
  EXPECT_EQ(r.overall.meanAbs, 0.5 / n);
  EXPECT_EQ(r.overall.rmse, std::sqrt(0.25 / n));
  EXPECT_NEAR(r.overall.psnr, 10.0 * std::log10(n / 0.25), 1e-12);
  EXPECT_EQ(r.overall.failingPixels, 1u);
  EXPECT_EQ(r.overall.failingFraction, 1.0 / n);
  EXPECT_EQ(r.overall.maxX, 5);
  EXPECT_EQ(r.overall.maxY, 2);
  EXPECT_EQ(r.pixelMaxAbs[2 * w + 5], 0.5f);
  EXPECT_EQ(r.peak, 1.0);
}

TEST(ImageDiff, StatisticsCoverEveryPixelAndChannel) {
  // Two channels, one pixel of four off by 0.5 in R only: the mean is over 8 samples.
  const FloatImage a = image(2, 2, {"R", "G"});
  FloatImage b = a;
  b.at(1, 0, 0) = 0.75f;
  DiffOptions options;
  options.perChannel = true;
  const DiffResult r = compareImages(a, b, options);
  EXPECT_EQ(r.overall.meanAbs, 0.5 / 8);
  EXPECT_EQ(r.overall.rmse, std::sqrt(0.25 / 8));
  EXPECT_EQ(r.overall.failingPixels, 1u);
  EXPECT_EQ(r.perChannel[0].meanAbs, 0.5 / 4);
  EXPECT_EQ(r.perChannel[0].failingPixels, 1u);
  EXPECT_EQ(r.perChannel[0].maxX, 1);
  EXPECT_EQ(r.perChannel[0].maxY, 0);
  EXPECT_EQ(r.perChannel[1].maxAbs, 0.0);
  EXPECT_EQ(r.perChannel[1].failingPixels, 0u);
}

TEST(ImageDiff, MaxLocationIsTheFirstInReadingOrder) {
  const FloatImage a = image(4, 3, {"R"});
  FloatImage b = a;
  b.at(3, 2, 0) = 1.0f;
  b.at(2, 1, 0) = 1.0f;  // same difference, earlier row
  b.at(0, 2, 0) = 0.5f;
  const DiffResult r = compareImages(a, b, {});
  EXPECT_EQ(r.overall.maxX, 2);
  EXPECT_EQ(r.overall.maxY, 1);
}

TEST(ImageDiff, ComparesChannelsSharedByName) {
  FloatImage a = image(3, 2, {"R", "G", "B", "A", "Z"});
  FloatImage b = image(3, 2, {"P.X", "B", "G", "R"});
  // A difference in a channel only A has is ignored; shared ones match by name, not position.
  a.at(0, 0, 4) = 100.0f;
  b.at(1, 1, 1) = 0.5f;  // b's B
  const DiffResult r = compareImages(a, b, {});
  EXPECT_EQ(r.overall.channels, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_FLOAT_EQ(r.overall.maxAbs, 0.25);
  EXPECT_EQ(r.overall.maxX, 1);
  EXPECT_EQ(r.overall.maxY, 1);

  DiffOptions only;
  only.channels = {"G", "R"};
  const DiffResult restricted = compareImages(a, b, only);
  EXPECT_EQ(restricted.overall.channels, (std::vector<std::string>{"G", "R"}));
  EXPECT_EQ(restricted.overall.maxAbs, 0.0);
}

TEST(ImageDiff, ErrorsNameTheImages) {
  const FloatImage a = image(4, 4, {"R", "G", "B"});
  DiffOptions options;
  options.labelA = "a.png";
  options.labelB = "b.exr";
  try {
    compareImages(a, image(4, 3, {"R", "G", "B"}), options);
    FAIL() << "no error for different sizes";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "b.exr: size 4x3 differs from a.png's 4x4");
  }
  try {
    compareImages(a, image(4, 4, {"P.X", "P.Y"}), options);
    FAIL() << "no error without shared channels";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "a.png and b.exr share no channel (a.png: R,G,B; b.exr: P.X,P.Y)");
  }
  options.channels = {"R", "A"};
  try {
    compareImages(a, image(4, 4, {"R", "A"}), options);
    FAIL() << "no error for a missing channel";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "a.png: no channel \"A\" (has R,G,B)");
  }
}

TEST(ImageDiff, ThresholdIsExclusive) {
  const FloatImage a = image(4, 1, {"R", "G"}, 0.0f);
  FloatImage b = a;
  b.at(0, 0, 0) = 0.25f;   // exactly at the threshold: passes
  b.at(1, 0, 1) = 0.375f;  // above it in one channel: fails
  b.at(2, 0, 0) = 0.125f;  // below
  DiffOptions options;
  options.threshold = 0.25;
  options.perChannel = true;
  const DiffResult r = compareImages(a, b, options);
  EXPECT_EQ(r.overall.failingPixels, 1u);
  EXPECT_EQ(r.overall.failingFraction, 0.25);
  EXPECT_EQ(r.perChannel[0].failingPixels, 0u);
  EXPECT_EQ(r.perChannel[1].failingPixels, 1u);

  options.threshold = 0.0;  // the default: any difference fails
  EXPECT_EQ(compareImages(a, b, options).overall.failingPixels, 3u);
}

TEST(ImageDiff, PeakIsTheReferenceMaximumUnlessGiven) {
  FloatImage a = image(2, 1, {"R", "G"}, 0.0f);
  a.at(0, 0, 0) = 4.0f;
  a.at(1, 0, 1) = std::numeric_limits<float>::infinity();  // ignored
  FloatImage b = a;
  b.at(1, 0, 0) = 1.0f;  // one of 4 samples off by 1: MSE 0.25
  const DiffResult r = compareImages(a, b, {});
  EXPECT_EQ(r.peak, 4.0);
  EXPECT_NEAR(r.overall.psnr, 10.0 * std::log10(16.0 / 0.25), 1e-12);
  DiffOptions options;
  options.peak = 1.0;
  EXPECT_NEAR(compareImages(a, b, options).overall.psnr, 10.0 * std::log10(4.0), 1e-12);
  EXPECT_EQ(compareImages(image(1, 1, {"R"}, -2.0f), image(1, 1, {"R"}), {}).peak, 1.0);
}

TEST(ImageDiff, NonFiniteValues) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  FloatImage a = image(3, 1, {"R"});
  a.at(0, 0, 0) = nan;
  a.at(1, 0, 0) = inf;
  FloatImage b = a;
  EXPECT_EQ(compareImages(a, b, {}).overall.maxAbs, 0.0);  // NaN = NaN, inf = inf
  b.at(2, 0, 0) = nan;
  const DiffResult r = compareImages(a, b, {});
  EXPECT_TRUE(std::isinf(r.overall.maxAbs));
  EXPECT_EQ(r.overall.maxX, 2);
  EXPECT_EQ(r.overall.failingPixels, 1u);
}

TEST(ImageDiff, HeatColors) {
  EXPECT_EQ(heatColor(0.0), (std::array<std::uint8_t, 3>{0, 0, 0}));
  EXPECT_EQ(heatColor(1.0), (std::array<std::uint8_t, 3>{252, 255, 164}));
  EXPECT_EQ(heatColor(0.5), (std::array<std::uint8_t, 3>{188, 55, 84}));
  EXPECT_EQ(heatColor(0.05), (std::array<std::uint8_t, 3>{11, 6, 29}));  // halfway to 0.1
  EXPECT_EQ(heatColor(-1.0), heatColor(0.0));
  EXPECT_EQ(heatColor(7.0), heatColor(1.0));
  EXPECT_EQ(heatColor(std::nan("")), heatColor(1.0));
  // Brightness rises along the ramp, so more difference always reads as brighter.
  int previous = -1;
  for (int i = 0; i <= 100; ++i) {
    const auto c = heatColor(i / 100.0);
    const int luma = 2 * c[0] + 7 * c[1] + c[2];
    EXPECT_GE(luma, previous) << i;
    previous = luma;
  }
}

TEST(ImageDiff, HeatMapScalesTheDifference) {
  const FloatImage a = image(3, 1, {"R", "G", "B"}, 0.0f);
  FloatImage b = a;
  b.at(1, 0, 2) = 0.2f;
  b.at(2, 0, 0) = 0.4f;
  const DiffResult r = compareImages(a, b, {});
  EXPECT_FLOAT_EQ(defaultHeatScale(r), 0.4f);
  const std::vector<std::uint8_t> map = heatMap(r, defaultHeatScale(r));
  ASSERT_EQ(map.size(), 9u);
  EXPECT_EQ(std::vector<std::uint8_t>(map.begin(), map.begin() + 3),
            (std::vector<std::uint8_t>{0, 0, 0}));
  EXPECT_EQ(std::vector<std::uint8_t>(map.begin() + 3, map.begin() + 6),
            (std::vector<std::uint8_t>{188, 55, 84}));  // 0.2 of 0.4
  EXPECT_EQ(std::vector<std::uint8_t>(map.begin() + 6, map.end()),
            (std::vector<std::uint8_t>{252, 255, 164}));
  // A larger scale darkens; equal images scale by 1.
  EXPECT_EQ(heatMap(r, 0.8)[6], 188);
  EXPECT_EQ(defaultHeatScale(compareImages(a, a, {})), 1.0);
}

}  // namespace
}  // namespace omnishadow::image_diff_test
