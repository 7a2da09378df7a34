// The bytes of a decoded picture (renderer/scene/pixel_bytes.h): copies share them until one is
// changed, a change never shows through another copy or a Watch, and a Watch sees the bytes only
// while someone holds them.
#include "renderer/scene/pixel_bytes.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow::pixel_bytes_test {
namespace {

TEST(PixelBytes, CopiesShareTheBytesUntilOneChangesThem) {
  PixelBytes a = std::vector<std::uint8_t>{1, 2, 3, 4};
  const PixelBytes b = a;
  EXPECT_TRUE(a.sharesWith(b));
  const PixelBytes& reader = a;
  EXPECT_EQ(reader[2], 3);  // reading through a const object keeps them shared
  EXPECT_TRUE(a.sharesWith(b));
  a[2] = 30;
  EXPECT_FALSE(a.sharesWith(b));
  EXPECT_EQ(a, (std::vector<std::uint8_t>{1, 2, 30, 4}));
  EXPECT_EQ(b, (std::vector<std::uint8_t>{1, 2, 3, 4}));
  // Alone, the bytes change in place.
  const std::uint8_t* before = std::as_const(a).data();
  a[0] = 10;
  EXPECT_EQ(std::as_const(a).data(), before);
  // Every way to change them leaves the copy as it was.
  PixelBytes c = b, d = b, e = b;
  c.assign(2, 9);
  d.resize(1);
  e.insert(e.end(), {5, 6});
  EXPECT_EQ(c, (std::vector<std::uint8_t>{9, 9}));
  EXPECT_EQ(d, (std::vector<std::uint8_t>{1}));
  EXPECT_EQ(e, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(b, (std::vector<std::uint8_t>{1, 2, 3, 4}));
  for (std::uint8_t& byte : c) byte = 0;
  EXPECT_EQ(b, (std::vector<std::uint8_t>{1, 2, 3, 4}));
}

// A copied scene (a job posed at a time, Python's Scene.posed) keeps one copy of its pixels;
// changing the copy's texture leaves the source's.
TEST(PixelBytes, ACopiedSceneSharesItsPixelsAndChangesItsOwn) {
  Scene scene;
  Image image;
  image.width = 2;
  image.height = 1;
  image.rgba = {1, 2, 3, 4, 5, 6, 7, 8};
  scene.images.push_back(image);
  Scene copy = scene;
  EXPECT_TRUE(copy.images[0].rgba.sharesWith(scene.images[0].rgba));
  copy.images[0].rgba[7] = 0;
  EXPECT_EQ(scene.images[0].rgba[7], 8);
  EXPECT_EQ(copy.images[0].rgba[7], 0);
}

TEST(PixelBytes, AWatchSeesTheBytesWhileSomeoneHoldsThem) {
  PixelBytes::Watch watch;
  {
    PixelBytes held = std::vector<std::uint8_t>{7, 8};
    watch = held.watch();
    const PixelBytes seen = PixelBytes::lock(watch);
    EXPECT_TRUE(seen.sharesWith(held));
    EXPECT_FALSE(watch.expired());
  }
  EXPECT_TRUE(watch.expired());
  EXPECT_TRUE(PixelBytes::lock(watch).empty());
}

// Its only holder may not change watched bytes in place: a Watch may lock them at any time on
// another thread (DecodedImageCache), and must see them as they were. So they are copied first.
TEST(PixelBytes, WatchedBytesAreCopiedBeforeAChangeEvenByTheirOnlyHolder) {
  PixelBytes held = std::vector<std::uint8_t>{1, 2, 3};
  const PixelBytes::Watch watch = held.watch();
  const std::uint8_t* watched = std::as_const(held).data();
  held[0] = 100;
  EXPECT_NE(std::as_const(held).data(), watched);
  EXPECT_TRUE(watch.expired()) << "nothing holds the watched bytes any more";
  // The copy is not watched: later changes are made in place.
  const std::uint8_t* mine = std::as_const(held).data();
  held[1] = 200;
  EXPECT_EQ(std::as_const(held).data(), mine);
  EXPECT_EQ(held, (std::vector<std::uint8_t>{100, 200, 3}));
}

TEST(PixelBytes, EmptyBytesAreEqualAndOwnNothing) {
  const PixelBytes none;
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.size(), 0u);
  EXPECT_EQ(none, PixelBytes{});
  EXPECT_EQ(none, std::vector<std::uint8_t>{});
  EXPECT_TRUE(static_cast<const std::vector<std::uint8_t>&>(none).empty());
  PixelBytes grown;
  grown.resize(3);
  EXPECT_EQ(grown, (std::vector<std::uint8_t>{0, 0, 0}));
  EXPECT_FALSE(PixelBytes::lock(PixelBytes().watch()).size());
}

}  // namespace
}  // namespace omnishadow::pixel_bytes_test
