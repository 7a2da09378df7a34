// Decoded pictures kept by the bytes they were decoded from (renderer/scene/decoded_image_cache.h):
// a load of the same image bytes takes the picture a scene still holds, or waits for the load
// that is decoding it; a picture nobody holds is decoded again; and loads through the cache give
// the scenes a load without it gives.
#include "renderer/scene/decoded_image_cache.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include "renderer/output/png_encoder.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/support/extension_textures.h"
#include "tests/support/temp_folder.h"
#include "tests/support/textured_triangle.h"

namespace omnishadow::decoded_image_cache_test {
namespace {

using Picture = DecodedImageCache::Picture;

const std::vector<unsigned char> kBytes = {1, 2, 3, 4, 5, 6, 7, 8};

Picture picture(std::uint8_t fill) {
  return {2, 1, "image/png", {"a warning"}, std::vector<std::uint8_t>(8, fill)};
}

TEST(DecodedImageCache, APictureIsTakenWhileSomeoneHoldsItAndDecodedAgainAfter) {
  DecodedImageCache cache;
  Picture decoded = picture(9);
  {
    const DecodedImageCache::Lookup first = cache.find(kBytes.data(), kBytes.size());
    ASSERT_FALSE(first.picture);
    ASSERT_TRUE(first.claim);
    cache.fulfil(first.claim, decoded);
  }
  {
    const DecodedImageCache::Lookup again = cache.find(kBytes.data(), kBytes.size());
    ASSERT_TRUE(again.picture);
    EXPECT_FALSE(again.claim);
    EXPECT_TRUE(again.picture->rgba.sharesWith(decoded.rgba));
    EXPECT_EQ(again.picture->width, 2);
    EXPECT_EQ(again.picture->height, 1);
    EXPECT_EQ(again.picture->mimeType, "image/png");
    EXPECT_EQ(again.picture->warnings, std::vector<std::string>{"a warning"});
    EXPECT_EQ(cache.size(), 1u);
  }
  // Other bytes of the same length are another picture.
  const std::vector<unsigned char> other = {1, 2, 3, 4, 5, 6, 7, 9};
  EXPECT_TRUE(cache.find(other.data(), other.size()).claim);
  // Once nobody holds the pixels, the cache has none to give: the bytes are decoded again.
  decoded = {};
  EXPECT_EQ(cache.size(), 0u);
  const DecodedImageCache::Lookup gone = cache.find(kBytes.data(), kBytes.size());
  EXPECT_FALSE(gone.picture);
  EXPECT_TRUE(gone.claim);
}

// A load that meets bytes another load is decoding waits for that picture instead of decoding
// them too; when that load cannot decode them, the waiting one decodes them itself.
TEST(DecodedImageCache, BytesBeingDecodedAreWaitedFor) {
  for (const bool decodes : {true, false}) {
    SCOPED_TRACE(decodes ? "fulfilled" : "abandoned");
    DecodedImageCache cache;
    const DecodedImageCache::Lookup first = cache.find(kBytes.data(), kBytes.size());
    ASSERT_TRUE(first.claim);
    std::atomic<bool> asked{false}, answered{false};
    std::future<DecodedImageCache::Lookup> second = std::async(std::launch::async, [&] {
      asked = true;
      DecodedImageCache::Lookup lookup = cache.find(kBytes.data(), kBytes.size());
      answered = true;
      return lookup;
    });
    while (!asked) std::this_thread::yield();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_FALSE(answered) << "the second load did not wait for the first one's decoding";
    const Picture decoded = picture(4);
    if (decodes) {
      cache.fulfil(first.claim, decoded);
    } else {
      cache.abandon(first.claim);
    }
    const DecodedImageCache::Lookup lookup = second.get();
    EXPECT_FALSE(lookup.claim);
    ASSERT_EQ(lookup.picture.has_value(), decodes);
    if (decodes) {
      EXPECT_TRUE(lookup.picture->rgba.sharesWith(decoded.rgba));
    }
  }
}

// Files holding the same PNG bytes (in a bufferView, a file, a data: URI): a later load through
// the cache takes the first scene's pixels, the same picture a load without the cache decodes.
TEST(DecodedImageCache, LoadsOfFilesWithTheSameImageBytesShareThePicture) {
  test_support::TempFolder folder("decoded-image-cache");
  const std::vector<std::uint8_t> rgba = test_support::cornersPictureRgba(128, 64);
  const std::string png = encodePng(128, 64, 4, rgba);
  const test_support::SceneImage image{std::vector<unsigned char>(png.begin(), png.end()), "tex",
                                       "image/png", "tex.png", ""};
  const auto a = test_support::writeTexturedTriangle(folder.path(), {image},
                                                     test_support::ImageStorage::BufferView, "a");
  const auto b = test_support::writeTexturedTriangle(folder.path(), {image},
                                                     test_support::ImageStorage::File, "b");
  DecodedImageCache cache;
  GltfLoadOptions options;
  options.decodedImages = &cache;
  const Scene first = loadGltf(a, options);
  const Scene second = loadGltf(b, options);
  const Scene alone = loadGltf(b);
  // A data: URI of 1 KiB and more is decoded by the reader and its picture by the loader's
  // threads, as a file's (gltf_data_uris.h).
  ASSERT_GE(png.size() * 4 / 3, 1024u);
  const Scene third =
      loadGltf(test_support::writeTexturedTriangle(folder.path(), {image},
                                                   test_support::ImageStorage::DataUri, "c"),
               options);
  ASSERT_EQ(third.images.size(), 1u);
  EXPECT_TRUE(third.images[0].rgba.sharesWith(first.images[0].rgba));
  EXPECT_EQ(third.warnings, alone.warnings);
  ASSERT_EQ(first.images.size(), 1u);
  ASSERT_EQ(second.images.size(), 1u);
  EXPECT_TRUE(second.images[0].rgba.sharesWith(first.images[0].rgba));
  EXPECT_EQ(second.images[0].rgba, alone.images[0].rgba);
  EXPECT_EQ(second.images[0].rgba, rgba);
  EXPECT_EQ(second.images[0].width, 128);
  EXPECT_EQ(second.images[0].height, 64);
  EXPECT_EQ(second.images[0].format, alone.images[0].format);
  EXPECT_EQ(second.warnings, alone.warnings);
  EXPECT_FALSE(alone.images[0].rgba.sharesWith(first.images[0].rgba));
}

}  // namespace
}  // namespace omnishadow::decoded_image_cache_test
