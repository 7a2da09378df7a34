// Regions of texels as disjoint rectangles (renderer/view/texel_region.h): the union of a frame's
// draws' rectangles, which its readback visits and nothing outside of which it may have drawn.
#include "renderer/view/texel_region.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace omnishadow::texel_region_test {
namespace {

// How many of `rects` hold each texel of a `width` x `height` view, row by row.
std::vector<int> coverage(const std::vector<TexelRect>& rects, int width, int height) {
  std::vector<int> count(static_cast<std::size_t>(width) * height, 0);
  for (const TexelRect& r : rects)
    for (int y = std::max(r.y0, 0); y < std::min(r.y1, height); ++y)
      for (int x = std::max(r.x0, 0); x < std::min(r.x1, width); ++x)
        ++count[static_cast<std::size_t>(y) * width + x];
  return count;
}

// Rectangles placed and sized by a linear congruential generator, some reaching past the view.
std::vector<TexelRect> randomRects(std::uint32_t seed, int count, int width, int height) {
  std::uint32_t state = seed;
  const auto next = [&](int below) {
    state = state * 1664525u + 1013904223u;
    return static_cast<int>((state >> 8) % static_cast<std::uint32_t>(below));
  };
  std::vector<TexelRect> rects;
  for (int i = 0; i < count; ++i) {
    const int x0 = next(width + 20) - 10, y0 = next(height + 20) - 10;
    rects.push_back({x0, y0, x0 + 1 + next(width / 3), y0 + 1 + next(height / 3)});
  }
  return rects;
}

void expectWellFormed(const TexelRegion& region) {
  const std::vector<TexelRect>& rects = region.rects();
  for (std::size_t i = 0; i < rects.size(); ++i) {
    EXPECT_FALSE(rects[i].empty());
    if (i > 0) {
      const TexelRect& a = rects[i - 1];
      const TexelRect& b = rects[i];
      EXPECT_TRUE(a.y0 < b.y0 || (a.y0 == b.y0 && a.x0 < b.x0)) << "rectangle " << i;
    }
    for (std::size_t j = i + 1; j < rects.size(); ++j)
      EXPECT_TRUE(rects[i].intersected(rects[j]).empty()) << "rectangles " << i << ", " << j;
  }
}

TEST(TexelRegion, AUnionHoldsExactlyTheTexelsOfItsRectanglesWithinTheClip) {
  const int width = 160, height = 120;
  const TexelRect clip{0, 0, width, height};
  int exact = 0;
  for (std::uint32_t seed = 1; seed <= 200; ++seed) {
    const std::vector<TexelRect> rects =
        randomRects(seed, 1 + static_cast<int>(seed % 12), width, height);
    const TexelRegion region = TexelRegion::unionOf(rects, clip, 1000);
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    expectWellFormed(region);
    const std::vector<int> want = coverage(rects, width, height);
    const std::vector<int> got = coverage(region.rects(), width, height);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < want.size(); ++i) wrong += (want[i] > 0 ? 1 : 0) != got[i];
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(region.texels(),
              std::count_if(want.begin(), want.end(), [](int n) { return n > 0; }));
    exact += region.rects().size() > 1;
  }
  EXPECT_GT(exact, 150);  // most unions took several rectangles
}

TEST(TexelRegion, NeighboursMergeAndTheRestStaysApart) {
  const TexelRect clip{0, 0, 100, 100};
  // Side by side, then one above the other with the same columns: one rectangle each time.
  EXPECT_EQ(TexelRegion::unionOf({{0, 0, 10, 10}, {10, 0, 30, 10}}, clip).rects(),
            (std::vector<TexelRect>{{0, 0, 30, 10}}));
  EXPECT_EQ(TexelRegion::unionOf({{5, 0, 30, 10}, {5, 10, 30, 40}}, clip).rects(),
            (std::vector<TexelRect>{{5, 0, 30, 40}}));
  // One inside another adds nothing.
  EXPECT_EQ(TexelRegion::unionOf({{0, 0, 50, 50}, {10, 10, 20, 20}}, clip).rects(),
            (std::vector<TexelRect>{{0, 0, 50, 50}}));
  // Apart in both directions: two, and not their bounding rectangle.
  EXPECT_EQ(TexelRegion::unionOf({{60, 70, 90, 95}, {0, 0, 10, 10}}, clip).rects(),
            (std::vector<TexelRect>{{0, 0, 10, 10}, {60, 70, 90, 95}}));
  // An L: a row band with one span and one with another.
  EXPECT_EQ(TexelRegion::unionOf({{0, 0, 10, 40}, {0, 30, 50, 40}}, clip).rects(),
            (std::vector<TexelRect>{{0, 0, 10, 30}, {0, 30, 50, 40}}));
}

TEST(TexelRegion, ClipsAndLeavesOutEmptyRectangles) {
  const TexelRect clip{0, 0, 64, 48};
  EXPECT_TRUE(TexelRegion::unionOf({}, clip).empty());
  EXPECT_TRUE(TexelRegion::unionOf({{70, 0, 90, 10}, {5, 5, 5, 9}}, clip).empty());
  EXPECT_TRUE(TexelRegion(TexelRect{3, 3, 3, 10}).empty());
  EXPECT_EQ(TexelRegion::unionOf({{-5, -5, 10, 10}, {60, 40, 80, 60}}, clip).rects(),
            (std::vector<TexelRect>{{0, 0, 10, 10}, {60, 40, 64, 48}}));
  const TexelRegion two = TexelRegion::unionOf({{0, 0, 10, 10}, {20, 20, 40, 30}}, clip);
  EXPECT_EQ(two.bounds(), (TexelRect{0, 0, 40, 30}));
  EXPECT_EQ(two.texels(), 100 + 200);
  EXPECT_EQ(two.largestRectTexels(), 200);
  EXPECT_EQ(two.clipped({5, 5, 25, 25}).rects(),
            (std::vector<TexelRect>{{5, 5, 10, 10}, {20, 20, 25, 25}}));
  EXPECT_TRUE(two.clipped({11, 0, 19, 48}).empty());
  EXPECT_TRUE(TexelRegion().bounds().empty());
}

TEST(TexelRegion, TooManyRectanglesCoarsenOntoTheGridThenIntoTheirBounds) {
  const int width = 1280, height = 720;
  const TexelRect clip{0, 0, width, height};
  const int grid = TexelRegion::kCoarseGrid;
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    const std::vector<TexelRect> rects = randomRects(seed, 30, width, height);
    const std::size_t exactCount = TexelRegion::unionOf(rects, clip, 100000).rects().size();
    for (const std::size_t cap : {std::size_t{1}, std::size_t{4}, std::size_t{16}}) {
      const TexelRegion region = TexelRegion::unionOf(rects, clip, cap);
      expectWellFormed(region);
      EXPECT_LE(region.rects().size(), cap);
      // Every texel of the rectangles within the clip, and nothing outside the clip.
      const std::vector<int> want = coverage(rects, width, height);
      const std::vector<int> got = coverage(region.rects(), width, height);
      std::size_t missing = 0;
      for (std::size_t i = 0; i < want.size(); ++i) missing += want[i] > 0 && got[i] == 0;
      EXPECT_EQ(missing, 0u);
      EXPECT_TRUE(region.bounds().intersected(clip) == region.bounds());
      if (exactCount <= cap) continue;
      // Coarsened: edges on the grid or the clip, or one bounding rectangle.
      if (region.rects().size() == 1) continue;
      for (const TexelRect& r : region.rects()) {
        EXPECT_TRUE(r.x0 % grid == 0 && r.y0 % grid == 0);
        EXPECT_TRUE(r.x1 % grid == 0 || r.x1 == width);
        EXPECT_TRUE(r.y1 % grid == 0 || r.y1 == height);
      }
    }
  }
}

TEST(TexelRegion, ThousandsOfRectanglesComeOutAsTheirBoundsOrTheGridAndHoldThemAll) {
  const int width = 2048, height = 2048;
  const TexelRect clip{0, 0, width, height};
  // 20,000 small rectangles scattered over a large view: past both sweeps' input limits.
  std::vector<TexelRect> rects;
  std::uint32_t state = 7u;
  for (int i = 0; i < 20000; ++i) {
    state = state * 1664525u + 1013904223u;
    const int x = static_cast<int>((state >> 8) % 2040u);
    state = state * 1664525u + 1013904223u;
    const int y = static_cast<int>((state >> 8) % 2040u);
    rects.push_back({x, y, x + 5, y + 5});
  }
  const TexelRegion region = TexelRegion::unionOf(rects, clip);
  expectWellFormed(region);
  EXPECT_LE(region.rects().size(), TexelRegion::kMaxRects);
  TexelRect bounding;
  for (const TexelRect& r : rects) bounding = bounding.united(r);
  EXPECT_EQ(region.bounds(), bounding);
  const std::vector<int> got = coverage(region.rects(), width, height);
  std::size_t missing = 0;
  for (const TexelRect& r : rects)
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x)
        missing += got[static_cast<std::size_t>(y) * width + x] == 0;
  EXPECT_EQ(missing, 0u);
}

}  // namespace
}  // namespace omnishadow::texel_region_test
