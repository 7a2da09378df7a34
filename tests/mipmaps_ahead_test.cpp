// Mipmaps made by the loader (GltfLoadOptions::mipmaps, makeMipmapsAhead): each sampled image
// gets mipmapChain()'s levels for the color space of its first use, and the upload takes
// those levels instead of making its own, only for that color space.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/image_mipmaps.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow {
namespace {

Image noise(int width, int height, std::uint32_t seed) {
  Image image;
  image.name = "noise" + std::to_string(seed);
  image.width = width;
  image.height = height;
  for (int i = 0; i < width * height * 4; ++i) {
    seed = seed * 1664525u + 1013904223u;
    image.rgba.push_back(static_cast<std::uint8_t>(seed >> 24));
  }
  return image;
}

// Four images: base color (sRGB), normal map (linear), unused, and one used first as occlusion
// (linear), then as emissive (sRGB).
TEST(MipmapsAhead, EachSampledImageGetsTheChainOfItsFirstUse) {
  Scene scene;
  for (std::uint32_t i = 0; i < 4; ++i) {
    scene.images.push_back(noise(16, 8, i + 1));
    scene.textures.push_back({static_cast<int>(i), {}});
  }
  Material first;
  first.baseColorTexture.texture = 0;
  first.normalTexture.texture = 1;
  first.occlusionTexture.texture = 3;
  Material second;
  second.emissiveTexture.texture = 3;
  scene.materials = {first, second};
  makeMipmapsAhead(scene);
  const bool expectedSrgb[] = {true, false, false, false};
  for (std::size_t i : {0u, 1u, 3u}) {
    SCOPED_TRACE(i);
    EXPECT_EQ(scene.images[i].mipmapsSrgb, expectedSrgb[i]);
    const std::vector<Image> chain = mipmapChain(scene.images[i], expectedSrgb[i]);
    ASSERT_EQ(scene.images[i].mipmaps.size(), chain.size());
    for (std::size_t level = 0; level < chain.size(); ++level)
      EXPECT_EQ(scene.images[i].mipmaps[level].rgba, chain[level].rgba);
  }
  EXPECT_TRUE(scene.images[2].mipmaps.empty());
}

// BoxTextured seen from afar, so that its texture is sampled from its smaller levels.
class MipmapsAheadRender : public ::testing::Test {
 protected:
  std::vector<std::uint8_t> draw(const Scene& scene) {
    Light light;
    light.name = "key";
    light.position = {3.0f, 4.0f, 5.0f};
    light.intensity = 40.0f;
    const ViewCamera camera = test_support::lookFrom(scene, {4.0f, 3.0f, 6.0f}, {0, 0, 0}, 64, 48);
    return test_support::renderSrgb8(scene, {light}, camera, glm::vec3(0.05f));
  }
  static Scene load(bool mipmaps) {
    GltfLoadOptions options;
    options.mipmaps = mipmaps;
    return loadGltf(
        std::string(OMNISHADOW_SOURCE_DIR) + "/scenes/thirdparty/BoxTextured/BoxTextured.glb",
        options);
  }
  // The scene with the alpha of its texture's first texel set to `alpha` (an opaque material:
  // the picture does not change, but the renderer's texture cache, which tells images apart by
  // their base level, holds nothing for it) and, when `fake` is set, levels of a uniform
  // magenta for `srgb` in place of the loader's.
  static Scene variant(const Scene& loaded, std::uint8_t alpha, bool fake, bool srgb) {
    Scene scene = loaded;
    Image& image = scene.images.at(0);
    image.rgba[3] = alpha;
    image.mipmaps.clear();
    if (fake) {
      for (const Image& level : mipmapChain(image, true)) {
        Image magenta = level;
        for (std::size_t i = 0; i < magenta.rgba.size(); i += 4)
          magenta.rgba[i] = 255, magenta.rgba[i + 1] = 0, magenta.rgba[i + 2] = 255;
        image.mipmaps.push_back(magenta);
      }
      image.mipmapsSrgb = srgb;
    }
    return scene;
  }
};

TEST_F(MipmapsAheadRender, TheUploadTakesTheLoadersLevelsForTheirColorSpaceOnly) {
  const Scene ahead = load(true);
  const Image& texture = ahead.images.at(0);
  ASSERT_FALSE(texture.mipmaps.empty());
  EXPECT_TRUE(texture.mipmapsSrgb);  // BoxTextured's one texture is its base color
  const std::vector<std::uint8_t> picture = draw(ahead);
  EXPECT_EQ(draw(load(false)), picture);
  EXPECT_EQ(draw(variant(ahead, 254, false, true)), picture);  // made by the upload
  EXPECT_NE(draw(variant(ahead, 253, true, true)), picture) << "the loader's levels were not used";
  EXPECT_EQ(draw(variant(ahead, 252, true, false)), picture);  // made for linear: not used
}

}  // namespace
}  // namespace omnishadow
