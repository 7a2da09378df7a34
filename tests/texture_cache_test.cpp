// Scene textures kept from one render to the next (renderer/passes/texture_cache.h): found
// again only for the same image bytes, size and color space; a render of a changed image
// draws the change.
#include "renderer/passes/texture_cache.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::texture_cache_test {
namespace {

Image image(int width, int height, std::uint8_t fill) {
  Image out;
  out.width = width;
  out.height = height;
  out.rgba.assign(static_cast<std::size_t>(width) * height * 4, fill);
  return out;
}

// The cache calls `make` only for what it does not hold (the same bytes, size and color
// space); it holds what was found since the last dropUnused().
TEST(TextureCache, MakesATextureOncePerImageAndColorSpace) {
  test_support::sharedRenderer();  // its GL context is current here
  TextureCache cache;
  int made = 0;
  const auto maker = [&](const Image& from, bool srgb) {
    return [&made, &from, srgb] {
      ++made;
      gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
      glTextureStorage2D(texture.get(), 1, srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, from.width,
                         from.height);
      glTextureSubImage2D(texture.get(), 0, 0, 0, from.width, from.height, GL_RGBA,
                          GL_UNSIGNED_BYTE, from.rgba.data());
      return texture;
    };
  };
  Image a = image(4, 2, 7);
  a.rgba[5] = 200;  // sRGB texels read back as stored, not decoded
  const auto first = cache.find(a, true, maker(a, true));
  EXPECT_EQ(cache.find(a, true, maker(a, true)), first);
  EXPECT_EQ(made, 1);
  cache.find(a, false, maker(a, false));  // linear: another texture
  EXPECT_EQ(made, 2);
  const Image tall = image(2, 4, 7);  // the same bytes, another shape
  cache.find(tall, true, maker(tall, true));
  EXPECT_EQ(made, 3);
  Image changed = a;
  changed.rgba[13] ^= 1;  // one bit
  const auto other = cache.find(changed, true, maker(changed, true));
  EXPECT_EQ(made, 4);
  EXPECT_NE(other, first);
  EXPECT_EQ(cache.size(), 4u);
  // A byte between the sampled words (1024 words over 1 MiB, about 1 KiB apart): the
  // comparison of all bytes tells the two apart.
  const Image big = image(512, 512, 3);
  Image unsampled = big;
  unsampled.rgba[1500] = 4;
  const auto bigTexture = cache.find(big, false, maker(big, false));
  EXPECT_NE(cache.find(unsampled, false, maker(unsampled, false)), bigTexture);
  EXPECT_EQ(cache.find(big, false, maker(big, false)), bigTexture);
  EXPECT_EQ(made, 6);
  EXPECT_EQ(cache.size(), 6u);

  // Above 4 MiB the digest is taken in two halves on two threads: a byte in either half, away
  // from the sampled words, still tells two images apart, and the same bytes find the texture
  // again (its own digest taken once, from its first level read back, then kept).
  const Image huge = image(1100, 1000, 9);  // 4.4 MB
  const auto hugeTexture = cache.find(huge, false, maker(huge, false));
  for (const std::size_t at : {std::size_t{1500}, huge.rgba.size() - 1500}) {
    Image changedHalf = huge;
    changedHalf.rgba[at] = 10;
    EXPECT_NE(cache.find(changedHalf, false, maker(changedHalf, false)), hugeTexture) << at;
  }
  EXPECT_EQ(cache.find(huge, false, maker(huge, false)), hugeTexture);
  EXPECT_EQ(cache.find(huge, false, maker(huge, false)), hugeTexture);
  EXPECT_EQ(made, 9);
  EXPECT_EQ(cache.size(), 9u);

  cache.dropUnused();  // all nine were found since they were made: kept
  EXPECT_EQ(cache.size(), 9u);
  cache.find(a, true, maker(a, true));
  cache.dropUnused();  // only `a` (sRGB) was found since
  EXPECT_EQ(cache.size(), 1u);
  EXPECT_EQ(cache.find(a, true, maker(a, true)), first);
  EXPECT_EQ(made, 9);
}

// A digest passed in is taken as the image's (a renderer's for a scene revision it rendered
// before): not checked against the bytes, and filled in where the cache hashed them. A texture
// made for bytes whose digest was only passed in does not carry it: the next image with those
// bytes is compared with what the texture holds.
TEST(TextureCache, AKnownDigestIsTakenAsTheImagesAndFilledIn) {
  test_support::sharedRenderer();  // its GL context is current here
  const auto maker = [](const Image& from) {
    return [&from] {
      gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
      glTextureStorage2D(texture.get(), 1, GL_RGBA8, from.width, from.height);
      glTextureSubImage2D(texture.get(), 0, 0, 0, from.width, from.height, GL_RGBA,
                          GL_UNSIGNED_BYTE, from.rgba.data());
      return texture;
    };
  };
  const Image big = image(512, 512, 3);
  Image unsampled = big;  // a byte between the sampled words
  unsampled.rgba[1500] = 4;
  std::optional<TextureCache::Digest> bigDigest;
  {
    TextureCache cache;
    const auto texture = cache.find(big, false, maker(big), &bigDigest);
    EXPECT_FALSE(bigDigest);  // nothing compared: nothing hashed
    EXPECT_EQ(cache.find(big, false, maker(big), &bigDigest), texture);
    ASSERT_TRUE(bigDigest);  // hashed to compare, and handed back
    // Other bytes with big's digest passed in: taken for big's texture, unchecked.
    std::optional<TextureCache::Digest> passed = bigDigest;
    EXPECT_EQ(cache.find(unsampled, false, maker(unsampled), &passed), texture);
  }
  // Made for `unsampled` with big's digest passed in, beside another image of the same sample
  // (so that the digest was taken to compare): big's bytes do not find it.
  TextureCache cache;
  Image other = big;
  other.rgba[2500] = 5;
  cache.find(other, false, maker(other));
  std::optional<TextureCache::Digest> passed = bigDigest;
  const auto made = cache.find(unsampled, false, maker(unsampled), &passed);
  EXPECT_NE(cache.find(big, false, maker(big)), made);
}

// A textured box rendered again is the same picture; with its texture changed in memory and
// a new revision (Scene::revision) the next render shows the change (the cache does not hand
// back the old texture), and the original again is the first picture.
TEST(TextureCache, ARenderOfAChangedImageDrawsTheChange) {
  const Scene original = loadGltf(std::string(OMNISHADOW_SOURCE_DIR) +
                                  "/scenes/thirdparty/BoxTextured/BoxTextured.glb");
  ASSERT_FALSE(original.images.empty());
  Scene inverted = original;
  for (std::uint8_t& v : inverted.images[0].rgba) v = static_cast<std::uint8_t>(255 - v);
  inverted.revision = newSceneRevision();
  Light light;
  light.name = "key";
  light.position = {1.5f, 2.0f, 2.0f};
  light.intensity = 8.0f;
  const ViewCamera camera = test_support::lookFrom(original, {1.2f, 1.0f, 1.6f}, {0, 0, 0}, 64, 48);
  const auto draw = [&](const Scene& s) {
    return test_support::renderSrgb8(s, {light}, camera, glm::vec3(0.05f));
  };
  const std::vector<std::uint8_t> first = draw(original);
  EXPECT_EQ(draw(original), first);
  const std::vector<std::uint8_t> changed = draw(inverted);
  EXPECT_NE(changed, first);
  EXPECT_EQ(draw(original), first);
  EXPECT_EQ(draw(inverted), changed);
}

// Inverts every byte of `image` but the 1024 words TextureCache samples (texture_cache.cpp's
// sampleOf(): word i at (size - 8) * i / 1023), so that only a digest of all bytes sees it.
void invertAllButTheSampledWords(Image& image) {
  std::vector<bool> sampled(image.rgba.size(), false);
  for (std::size_t i = 0; i < 1024; ++i)
    for (std::size_t k = 0; k < 8; ++k) sampled[(image.rgba.size() - 8) * i / 1023 + k] = true;
  for (std::size_t k = 0; k < image.rgba.size(); ++k)
    if (!sampled[k]) image.rgba[k] = static_cast<std::uint8_t>(255 - image.rgba[k]);
}

// A scene changed in place, rendered again by the renderer that drew it twice (the second
// render compared its image with the kept texture, so hashed it). With the revision it had, the
// renderer takes its image for the one it hashed, by contract: a change the cache's sample of
// the bytes misses draws the earlier picture, one it sees is drawn. With revision 0 or a new
// revision every change is drawn.
TEST(TextureCache, TheSameRevisionIsTakenAsTheSameImages) {
  Scene scene = loadGltf(std::string(OMNISHADOW_SOURCE_DIR) +
                         "/scenes/thirdparty/BoxTextured/BoxTextured.glb");
  ASSERT_GT(scene.images[0].rgba.size(), 64u * 1024u);  // sampled words far apart
  Light light;
  light.name = "key";
  light.position = {1.5f, 2.0f, 2.0f};
  light.intensity = 8.0f;
  const ViewCamera camera = test_support::lookFrom(scene, {1.2f, 1.0f, 1.6f}, {0, 0, 0}, 64, 48);
  const auto draw = [&] {
    return test_support::renderSrgb8(scene, {light}, camera, glm::vec3(0.05f));
  };
  const std::vector<std::uint8_t> first = draw();
  EXPECT_EQ(draw(), first);
  const Image original = scene.images[0];
  invertAllButTheSampledWords(scene.images[0]);
  EXPECT_EQ(draw(), first);  // the contract broken: the image the revision stands for
  const std::uint64_t revision = scene.revision;
  scene.revision = 0;
  const std::vector<std::uint8_t> changed = draw();
  EXPECT_NE(changed, first);
  scene.revision = newSceneRevision();
  EXPECT_NE(scene.revision, revision);
  EXPECT_EQ(draw(), changed);
  scene.images[0] = original;
  scene.revision = newSceneRevision();
  EXPECT_EQ(draw(), first);
  EXPECT_EQ(draw(), first);
  // Every byte inverted, the sampled words too: drawn although the revision stayed.
  for (std::uint8_t& v : scene.images[0].rgba) v = static_cast<std::uint8_t>(255 - v);
  EXPECT_NE(draw(), first);
}

}  // namespace
}  // namespace omnishadow::texture_cache_test
