// WebP textures (EXT_texture_webp), decoded by libwebp (renderer/scene/webp_decoder.cpp): texels
// where the source put them from every kind of storage, the WebP drawn instead of its fallback,
// damaged, animated and oversized files refused by name, and a scene whose textures are WebP
// rendering the same picture as its PNG twin. The WebPs are made here with libwebp's encoder.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <tiny_gltf.h>
#include <webp/encode.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "renderer/scene/gltf_loader.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/cli_fixture.h"
#include "tests/support/extension_textures.h"
#include "tests/support/input_error.h"
#include "tests/support/temp_folder.h"
#include "tests/support/textured_triangle.h"

namespace omnishadow {
namespace {

using test_support::ImageStorage;
using test_support::inputError;
using test_support::TempFolder;
namespace fs = std::filesystem;

constexpr const char* kWebp = "EXT_texture_webp";

enum class Coding { Lossless, Lossy };

std::vector<unsigned char> encodeWebp(int width, int height, const std::vector<std::uint8_t>& rgba,
                                      Coding coding) {
  std::uint8_t* out = nullptr;
  const std::size_t size =
      coding == Coding::Lossless
          ? WebPEncodeLosslessRGBA(rgba.data(), width, height, width * 4, &out)
          : WebPEncodeRGBA(rgba.data(), width, height, width * 4, 100.0f, &out);
  std::vector<unsigned char> bytes(out, out + size);
  WebPFree(out);
  EXPECT_GT(size, 0u);
  return bytes;
}

builder::MeshData triangle() {
  builder::MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals.assign(3, glm::vec3(0, 0, 1));
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  return mesh;
}

test_support::SceneImage webpImage(std::vector<unsigned char> bytes) {
  return {std::move(bytes), "leaf", "image/webp", "leaf.webp", kWebp};
}

TEST(WebpTexture, LosslessWebpDecodesToTheSourceTexelsFromABufferViewAFileOrADataUri) {
  constexpr int kWidth = 37, kHeight = 23;
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(kWidth, kHeight);
  const std::vector<unsigned char> webp = encodeWebp(kWidth, kHeight, source, Coding::Lossless);
  for (ImageStorage storage :
       {ImageStorage::BufferView, ImageStorage::File, ImageStorage::DataUri}) {
    TempFolder folder("webp");
    const Scene scene =
        loadGltf(test_support::writeTexturedTriangle(folder.path(), {webpImage(webp)}, storage));
    ASSERT_EQ(scene.images.size(), 1u);
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].image, 0);
    const Image& image = scene.images[0];
    EXPECT_EQ(image.width, kWidth);
    EXPECT_EQ(image.height, kHeight);
    EXPECT_EQ(image.rgba, source) << "storage " << int(storage);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  }
}

// Lossy WebP codes color in 4:2:0 YUV, but its alpha losslessly (libwebp's default).
TEST(WebpTexture, LossyWebpIsWithinAFewStepsOfTheSourceAndKeepsItsAlphaExactly) {
  constexpr int kWidth = 64, kHeight = 48;
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(kWidth, kHeight);
  TempFolder folder("webp");
  const Scene scene = loadGltf(test_support::writeTexturedTriangle(
      folder.path(), {webpImage(encodeWebp(kWidth, kHeight, source, Coding::Lossy))},
      ImageStorage::BufferView));
  const Image& image = scene.images.at(0);
  EXPECT_LE(test_support::largestChannelDifference(image.rgba, source, 0, 3), 6);
  EXPECT_EQ(test_support::largestChannelDifference(image.rgba, source, 3, 1), 0);
  EXPECT_NE(image.rgba, source) << "lossless bytes from a lossy file: was it decoded?";
}

// The specification's example: a core PNG source for other viewers and the WebP for those that
// decode it. The WebP is drawn, and the PNG, which nothing else draws, is not decoded.
TEST(WebpTexture, TheWebpIsDrawnAndItsPngFallbackIsNotDecoded) {
  TempFolder folder("webp");
  builder::GltfBuilder builder;
  const int texture = builder.addTexture(2, 1, {0, 255, 0, 255, 0, 0, 255, 255}, "fallback");
  builder.addNode("quad", {}, builder.addTexturedMesh(triangle(), texture));
  tinygltf::Model& model = builder.model();
  const std::vector<std::uint8_t> red = {255, 0, 0, 255, 255, 0, 0, 128};
  tinygltf::Image webp;
  webp.mimeType = "image/webp";
  webp.bufferView = builder::appendBufferView(model, encodeWebp(2, 1, red, Coding::Lossless), 0, 0);
  model.images.push_back(webp);
  model.textures[0].extensions[kWebp] =
      tinygltf::Value(tinygltf::Value::Object{{"source", tinygltf::Value(1)}});
  model.extensionsUsed = {kWebp};
  const fs::path path = folder.path() / "scene.glb";
  builder.write(path, builder::FileFormat::Glb);
  const Scene scene = loadGltf(path);
  ASSERT_EQ(scene.images.size(), 2u);
  EXPECT_EQ(scene.textures.at(0).image, 1);
  EXPECT_TRUE(scene.images[0].rgba.empty());
  EXPECT_EQ(scene.images[1].rgba, red);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  EXPECT_TRUE(scene.source.extensions.at(0).supported);
}

TEST(WebpTexture, ADamagedWebpIsAnInputErrorNamingTheImage) {
  std::vector<unsigned char> webp =
      encodeWebp(64, 64, test_support::cornersPictureRgba(64, 64), Coding::Lossy);
  webp.resize(webp.size() * 2 / 3);
  for (ImageStorage storage : {ImageStorage::BufferView, ImageStorage::File}) {
    TempFolder folder("webp");
    const fs::path path =
        test_support::writeTexturedTriangle(folder.path(), {webpImage(webp)}, storage);
    EXPECT_EQ(inputError([&] { loadGltf(path); }),
              path.string() +
                  ": images[0] \"leaf\": cannot decode the WebP: the data ends early (a "
                  "truncated file)");
  }
  // Not a WebP at all after the RIFF header.
  std::vector<unsigned char> noise = {'R', 'I', 'F', 'F', 40,  0,   0,  0, 'W', 'E',
                                      'B', 'P', 'V', 'P', '8', ' ', 28, 0, 0,   0};
  noise.resize(48, 0x5A);
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(folder.path(), {webpImage(noise)},
                                                            ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"leaf\": no WebP header that can be decoded: damaged data (a "
                "bitstream error)");
}

// The extended format's header (VP8X) with the animation flag: EXT_texture_webp takes stills.
TEST(WebpTexture, AnAnimatedWebpIsRefusedNamingTheImage) {
  std::vector<unsigned char> animated = {'R',  'I', 'F', 'F', 22,  0,   0,  0,  'W', 'E',
                                         'B',  'P', 'V', 'P', '8', 'X', 10, 0,  0,   0,
                                         0x02, 0,   0,   0,   15,  0,   0,  15, 0,   0};
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(folder.path(), {webpImage(animated)},
                                                            ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"leaf\": an animated WebP (EXT_texture_webp takes still images)");
}

long peakResidentKiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// A lossless WebP header (VP8L: signature 0x2F, then width - 1 and height - 1 in 14 bits each)
// over a few bytes of data, claiming `side` x `side` texels.
std::vector<unsigned char> losslessClaim(std::uint32_t side) {
  std::vector<unsigned char> claim = {'R', 'I', 'F', 'F', 0,   0, 0, 0, 'W', 'E', 'B',
                                      'P', 'V', 'P', '8', 'L', 0, 0, 0, 0,   0x2F};
  const std::uint32_t bits = (side - 1) | (side - 1) << 14;
  for (int i = 0; i < 4; ++i) claim.push_back(static_cast<unsigned char>(bits >> (8 * i)));
  claim.resize(claim.size() + 27, 0x00);
  const auto putLe32 = [&](std::size_t at, std::size_t value) {
    for (int i = 0; i < 4; ++i) claim[at + i] = static_cast<unsigned char>(value >> (8 * i));
  };
  putLe32(4, claim.size() - 8);
  putLe32(16, claim.size() - 20);
  return claim;
}

// 11585^2 texels, 512 MB of RGBA and within the WebP limit: decoding fails, and what libwebp
// reserved for it is never touched.
TEST(WebpTexture, AHeaderClaimingHalfAGigabyteOverAFewBytesIsRefusedWithoutTouchingIt) {
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(
      folder.path(), {webpImage(losslessClaim(11585))}, ImageStorage::BufferView);
  const long before = peakResidentKiB();
  const std::string error = inputError([&] { loadGltf(path); });
  EXPECT_EQ(error.rfind(path.string() + ": images[0] \"leaf\": cannot decode the WebP: ", 0), 0u)
      << error;
  EXPECT_LT(peakResidentKiB() - before, 128 * 1024) << "KiB more at the peak";
}

// libwebp's lossless decoder holds the picture twice: WebP's limit is half the texels of the
// other formats', checked from the header.
TEST(WebpTexture, AWebpLargerThanTheWebpLimitIsRefusedFromItsHeader) {
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(
      folder.path(), {webpImage(losslessClaim(16383))}, ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"leaf\": 16383x16383 texels is too large (at most 32768 per side "
                "and 134217728 in all for WebP)");
}

// The CLI end to end: the box scene with its PNG textures turned into lossless WebP, drawn only
// through the extension (required, no fallback), renders byte for byte the PNG scene's picture.
class WebpSceneTest : public test_support::CliFixture {
 protected:
  WebpSceneTest() : CliFixture("webp-scene") {}
};

TEST_F(WebpSceneTest, ABoxSceneWithWebpTexturesRendersThePictureOfItsPngTwin) {
  const fs::path png = input("png/scene.gltf");
  test_support::writeBoxScene(png, {.format = builder::FileFormat::GltfEmbedded});
  const fs::path webp =
      test_support::withTexturesThrough(png, input("webp"), kWebp, "webp", [](const Image& image) {
        return encodeWebp(image.width, image.height, image.rgba, Coding::Lossless);
      });
  const Run fromPng =
      run({"render", png.string(), "-o", "png.png", "--width", "96", "--height", "64"});
  ASSERT_EQ(fromPng.status, 0) << fromPng.err;
  const Run fromWebp =
      run({"render", webp.string(), "-o", "webp.png", "--width", "96", "--height", "64"});
  ASSERT_EQ(fromWebp.status, 0) << fromWebp.err;
  EXPECT_EQ(fromWebp.err, "") << "no warning for a valid file";
  EXPECT_TRUE(test_support::sameBytes(output("png.png"), output("webp.png")));
}

// Every error path ends the same way: one line naming the file and the image, exit status 2,
// and no picture written.
TEST_F(WebpSceneTest, ADamagedWebpEndsTheRenderWithStatusTwoAndNoPicture) {
  const fs::path path = test_support::writeTexturedTriangle(
      in_, {webpImage({'R', 'I', 'F', 'F', 4, 0, 0, 0, 'W', 'E', 'B', 'P'})},
      ImageStorage::DataUri);
  const Run r = run({"render", path.string(), "-o", "broken.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(test_support::contains(r.err, path.string() + ": images[0]")) << r.err;
  EXPECT_FALSE(fs::exists(output("broken.png")));
}

}  // namespace
}  // namespace omnishadow
