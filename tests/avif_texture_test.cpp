// AVIF textures (EXT_texture_avif), decoded by libavif (renderer/scene/avif_decoder.cpp), which
// omnishadow loads only when it meets an AVIF: texels where the source put them from every kind
// of storage, the AVIF drawn instead of its fallback, damaged files and image sequences refused
// by name, a scene whose textures are AVIF rendering the same picture as its PNG twin, and
// libavif not loaded by scenes without AVIF. The AVIFs are made here with libavif's encoder.
#include <avif/avif.h>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstdint>
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

constexpr const char* kAvif = "EXT_texture_avif";

enum class Coding {
  Lossless,  // 4:4:4, the identity matrix (the planes are G, B, R), quantizer 0
  Lossy,     // 4:2:0, BT.601, quantizer 10
};

// `frames` copies of `rgba` (more than one: an image sequence).
std::vector<unsigned char> encodeAvif(int width, int height, const std::vector<std::uint8_t>& rgba,
                                      Coding coding, int frames = 1) {
  const bool lossless = coding == Coding::Lossless;
  avifImage* image =
      avifImageCreate(static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), 8,
                      lossless ? AVIF_PIXEL_FORMAT_YUV444 : AVIF_PIXEL_FORMAT_YUV420);
  image->yuvRange = AVIF_RANGE_FULL;
  if (lossless) image->matrixCoefficients = AVIF_MATRIX_COEFFICIENTS_IDENTITY;
  avifRGBImage rgb;
  avifRGBImageSetDefaults(&rgb, image);
  rgb.format = AVIF_RGB_FORMAT_RGBA;
  rgb.depth = 8;
  rgb.pixels = const_cast<std::uint8_t*>(rgba.data());
  rgb.rowBytes = static_cast<std::uint32_t>(width * 4);
  EXPECT_EQ(avifImageRGBToYUV(image, &rgb), AVIF_RESULT_OK);
  avifEncoder* encoder = avifEncoderCreate();
  encoder->speed = AVIF_SPEED_FASTEST;
  const int quantizer = lossless ? AVIF_QUANTIZER_LOSSLESS : 10;
  encoder->minQuantizer = encoder->maxQuantizer = quantizer;
  encoder->minQuantizerAlpha = encoder->maxQuantizerAlpha = AVIF_QUANTIZER_LOSSLESS;
  for (int f = 0; f < frames; ++f) {
    EXPECT_EQ(
        avifEncoderAddImage(encoder, image, 1,
                            frames == 1 ? AVIF_ADD_IMAGE_FLAG_SINGLE : AVIF_ADD_IMAGE_FLAG_NONE),
        AVIF_RESULT_OK);
  }
  avifRWData out = AVIF_DATA_EMPTY;
  EXPECT_EQ(avifEncoderFinish(encoder, &out), AVIF_RESULT_OK);
  std::vector<unsigned char> bytes(out.data, out.data + out.size);
  avifRWDataFree(&out);
  avifEncoderDestroy(encoder);
  avifImageDestroy(image);
  return bytes;
}

test_support::SceneImage avifImage(std::vector<unsigned char> bytes) {
  return {std::move(bytes), "stone", "image/avif", "stone.avif", kAvif};
}

TEST(AvifTexture, LosslessAvifDecodesToTheSourceTexelsFromABufferViewAFileOrADataUri) {
  constexpr int kWidth = 37, kHeight = 23;
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(kWidth, kHeight);
  const std::vector<unsigned char> avif = encodeAvif(kWidth, kHeight, source, Coding::Lossless);
  for (ImageStorage storage :
       {ImageStorage::BufferView, ImageStorage::File, ImageStorage::DataUri}) {
    TempFolder folder("avif");
    const Scene scene =
        loadGltf(test_support::writeTexturedTriangle(folder.path(), {avifImage(avif)}, storage));
    ASSERT_EQ(scene.images.size(), 1u);
    EXPECT_EQ(scene.textures.at(0).image, 0);
    const Image& image = scene.images[0];
    EXPECT_EQ(image.width, kWidth);
    EXPECT_EQ(image.height, kHeight);
    EXPECT_EQ(image.rgba, source) << "storage " << int(storage);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  }
}

TEST(AvifTexture, LossyAvifIsWithinAFewStepsOfTheSourceAndKeepsItsAlphaExactly) {
  constexpr int kWidth = 64, kHeight = 48;
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(kWidth, kHeight);
  TempFolder folder("avif");
  const Scene scene = loadGltf(test_support::writeTexturedTriangle(
      folder.path(), {avifImage(encodeAvif(kWidth, kHeight, source, Coding::Lossy))},
      ImageStorage::BufferView));
  const Image& image = scene.images.at(0);
  EXPECT_LE(test_support::largestChannelDifference(image.rgba, source, 0, 3), 6);
  EXPECT_EQ(test_support::largestChannelDifference(image.rgba, source, 3, 1), 0);
  EXPECT_NE(image.rgba, source) << "lossless bytes from a lossy file: was it decoded?";
}

// gltf-transform writes AVIF without a fallback; a file may still offer a PNG one, and a WebP
// too: the AVIF is drawn, and the images only the others reach are not decoded (the WebP here
// is no WebP at all: decoding it would fail the load).
TEST(AvifTexture, TheAvifIsDrawnAndTheTexturesOtherImagesAreNotDecoded) {
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(8, 4);
  TempFolder folder("avif");
  builder::GltfBuilder builder;
  builder::MeshData triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.normals.assign(3, glm::vec3(0, 0, 1));
  triangle.uvs = {{0, 0}, {1, 0}, {0, 1}};
  triangle.indices = {0, 1, 2};
  const int texture = builder.addTexture(1, 1, {0, 255, 0, 255}, "fallback");
  builder.addNode("triangle", {}, builder.addTexturedMesh(triangle, texture));
  tinygltf::Model& model = builder.model();
  const auto addImage = [&](const std::vector<unsigned char>& bytes, const char* mimeType) {
    tinygltf::Image image;
    image.mimeType = mimeType;
    image.bufferView = builder::appendBufferView(model, bytes, 0, 0);
    model.images.push_back(image);
    return tinygltf::Value(tinygltf::Value::Object{
        {"source", tinygltf::Value(static_cast<int>(model.images.size()) - 1)}});
  };
  model.textures[0].extensions[kAvif] =
      addImage(encodeAvif(8, 4, source, Coding::Lossless), "image/avif");
  model.textures[0].extensions["EXT_texture_webp"] =
      addImage({'R', 'I', 'F', 'F', 4, 0, 0, 0, 'W', 'E', 'B', 'P'}, "image/webp");
  model.extensionsUsed = {kAvif, "EXT_texture_webp"};
  const fs::path path = folder.path() / "scene.glb";
  builder.write(path, builder::FileFormat::Glb);
  const Scene scene = loadGltf(path);
  ASSERT_EQ(scene.images.size(), 3u);
  EXPECT_EQ(scene.textures.at(0).image, 1);
  EXPECT_TRUE(scene.images[0].rgba.empty());
  EXPECT_EQ(scene.images[1].rgba, source);
  EXPECT_TRUE(scene.images[2].rgba.empty());
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
}

TEST(AvifTexture, ADamagedAvifIsAnInputErrorNamingTheImage) {
  std::vector<unsigned char> avif =
      encodeAvif(64, 64, test_support::cornersPictureRgba(64, 64), Coding::Lossy);
  avif.resize(avif.size() * 2 / 3);
  for (ImageStorage storage : {ImageStorage::BufferView, ImageStorage::File}) {
    TempFolder folder("avif");
    const fs::path path =
        test_support::writeTexturedTriangle(folder.path(), {avifImage(avif)}, storage);
    const std::string error = inputError([&] { loadGltf(path); });
    EXPECT_EQ(error.rfind(path.string() + ": images[0] \"stone\": cannot ", 0), 0u) << error;
    EXPECT_NE(error.find("AVIF"), std::string::npos) << error;
  }
}

// Several frames make an image sequence (brand avis): EXT_texture_avif takes stills.
TEST(AvifTexture, AnAvifImageSequenceIsRefusedNamingTheImage) {
  const std::vector<unsigned char> sequence =
      encodeAvif(16, 16, test_support::cornersPictureRgba(16, 16), Coding::Lossy, 2);
  TempFolder folder("avif");
  const fs::path path = test_support::writeTexturedTriangle(folder.path(), {avifImage(sequence)},
                                                            ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"stone\": an AVIF image sequence (EXT_texture_avif "
                "takes still images)");
}

class AvifSceneTest : public test_support::CliFixture {
 protected:
  AvifSceneTest() : CliFixture("avif-scene") {}
};

// The box scene with its PNG textures turned into lossless AVIF, drawn only through the
// extension (required, no fallback), renders byte for byte the PNG scene's picture; libavif is
// loaded for the AVIF scene and not for the PNG one.
TEST_F(AvifSceneTest, ABoxSceneWithAvifTexturesRendersThePictureOfItsPngTwin) {
  const fs::path png = input("png/scene.gltf");
  test_support::writeBoxScene(png, {.format = builder::FileFormat::GltfEmbedded});
  const fs::path avif =
      test_support::withTexturesThrough(png, input("avif"), kAvif, "avif", [](const Image& image) {
        return encodeAvif(image.width, image.height, image.rgba, Coding::Lossless);
      });
  const std::vector<std::string> loads = {"LD_DEBUG=files"};
  const Run fromPng =
      run({"render", png.string(), "-o", "png.png", "--width", "96", "--height", "64"}, loads);
  ASSERT_EQ(fromPng.status, 0) << fromPng.err;
  EXPECT_NE(fromPng.err.find("libwebp"), std::string::npos) << "LD_DEBUG gave no list";
  EXPECT_EQ(fromPng.err.find("libavif"), std::string::npos);
  const Run fromAvif =
      run({"render", avif.string(), "-o", "avif.png", "--width", "96", "--height", "64"}, loads);
  ASSERT_EQ(fromAvif.status, 0) << fromAvif.err;
  EXPECT_NE(fromAvif.err.find("libavif"), std::string::npos);
  EXPECT_EQ(fromAvif.err.find("warning"), std::string::npos) << "no warning for a valid file";
  EXPECT_TRUE(test_support::sameBytes(output("png.png"), output("avif.png")));
}

}  // namespace
}  // namespace omnishadow
