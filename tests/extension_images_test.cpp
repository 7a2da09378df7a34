// Texture images that reach materials through extensions: WebP (EXT_texture_webp, decoded by
// libwebp, renderer/scene/webp_decoder.cpp) and AVIF (EXT_texture_avif, libavif, loaded only
// when a scene has one, renderer/scene/avif_decoder.cpp). For both: texels where the source put
// them from every kind of storage, lossy files close to their source, damaged files refused
// naming the image, and a scene whose textures are re-encoded rendering the same picture as its
// PNG twin. Then what is particular to each format. The images are made here with the
// libraries' encoders.
#include <avif/avif.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <tiny_gltf.h>
#include <webp/encode.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "renderer/scene/gltf_loader.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/cli_fixture.h"
#include "tests/support/extension_textures.h"
#include "tests/support/input_error.h"
#include "tests/support/temp_folder.h"
#include "tests/support/textured_triangle.h"

namespace omnishadow::extension_images_test {
namespace {

using test_support::ImageStorage;
using test_support::inputError;
using test_support::TempFolder;
namespace fs = std::filesystem;

constexpr const char* kWebp = "EXT_texture_webp";
constexpr const char* kAvif = "EXT_texture_avif";

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

// Lossless: 4:4:4, the identity matrix (the planes are G, B, R), quantizer 0. Lossy: 4:2:0,
// BT.601, quantizer 10. Alpha lossless in both. `frames` copies make an image sequence.
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
  encoder->minQuantizer = encoder->maxQuantizer = lossless ? AVIF_QUANTIZER_LOSSLESS : 10;
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

// One format, as the shared tests see it.
struct Format {
  std::string name;  // the test's name
  std::string extension, mimeType, suffix;
  std::function<std::vector<unsigned char>(int, int, const std::vector<std::uint8_t>&, Coding)>
      encode;
  std::string truncated;  // the error for a file cut to two thirds, after "images[0] "tex": "

  test_support::SceneImage image(std::vector<unsigned char> bytes) const {
    return {std::move(bytes), "tex", mimeType, "tex." + suffix, extension};
  }
};

const Format kFormats[] = {
    {"WebP", kWebp, "image/webp", "webp",
     [](int w, int h, const std::vector<std::uint8_t>& rgba, Coding coding) {
       return encodeWebp(w, h, rgba, coding);
     },
     "cannot decode the WebP: the data ends early (a truncated file)"},
    {"AVIF", kAvif, "image/avif", "avif",
     [](int w, int h, const std::vector<std::uint8_t>& rgba, Coding coding) {
       return encodeAvif(w, h, rgba, coding);
     },
     "cannot decode the AVIF: BMFF parsing failed (Item ID 1 extent offset failed size hint "
     "sanity check. Truncated data?)"},
};

class ExtensionImageTest : public ::testing::TestWithParam<Format> {};

TEST_P(ExtensionImageTest, LosslessFilesDecodeToTheSourceTexelsFromABufferViewAFileOrADataUri) {
  constexpr int kWidth = 37, kHeight = 23;
  const Format& format = GetParam();
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(kWidth, kHeight);
  const std::vector<unsigned char> bytes = format.encode(kWidth, kHeight, source, Coding::Lossless);
  for (ImageStorage storage :
       {ImageStorage::BufferView, ImageStorage::File, ImageStorage::DataUri}) {
    TempFolder folder("extension-image");
    const Scene scene = loadGltf(
        test_support::writeTexturedTriangle(folder.path(), {format.image(bytes)}, storage));
    ASSERT_EQ(scene.images.size(), 1u);
    EXPECT_EQ(scene.textures.at(0).image, 0);
    const Image& image = scene.images[0];
    EXPECT_EQ(image.width, kWidth);
    EXPECT_EQ(image.height, kHeight);
    EXPECT_EQ(image.rgba, source) << "storage " << int(storage);
    EXPECT_EQ(image.format, format.name);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    EXPECT_TRUE(scene.source.extensions.at(0).supported);
  }
}

// Both code color lossily in 4:2:0 YUV here, and alpha losslessly.
TEST_P(ExtensionImageTest, LossyFilesAreWithinAFewStepsOfTheSourceAndKeepTheirAlphaExactly) {
  constexpr int kWidth = 64, kHeight = 48;
  const Format& format = GetParam();
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(kWidth, kHeight);
  TempFolder folder("extension-image");
  const Scene scene = loadGltf(test_support::writeTexturedTriangle(
      folder.path(), {format.image(format.encode(kWidth, kHeight, source, Coding::Lossy))},
      ImageStorage::BufferView));
  const Image& image = scene.images.at(0);
  EXPECT_LE(test_support::largestChannelDifference(image.rgba, source, 0, 3), 6);
  EXPECT_EQ(test_support::largestChannelDifference(image.rgba, source, 3, 1), 0);
  EXPECT_NE(image.rgba, source) << "lossless bytes from a lossy file: was it decoded?";
}

TEST_P(ExtensionImageTest, ADamagedFileIsAnInputErrorNamingTheImage) {
  const Format& format = GetParam();
  std::vector<unsigned char> bytes =
      format.encode(64, 64, test_support::cornersPictureRgba(64, 64), Coding::Lossy);
  bytes.resize(bytes.size() * 2 / 3);
  for (ImageStorage storage : {ImageStorage::BufferView, ImageStorage::File}) {
    TempFolder folder("extension-image");
    const fs::path path =
        test_support::writeTexturedTriangle(folder.path(), {format.image(bytes)}, storage);
    EXPECT_EQ(inputError([&] { loadGltf(path); }),
              path.string() + ": images[0] \"tex\": " + format.truncated);
  }
}

class ExtensionImageSceneTest : public test_support::CliFixture,
                                public ::testing::WithParamInterface<Format> {
 protected:
  ExtensionImageSceneTest() : CliFixture("extension-image-scene") {}
};

// The box scene with its PNG textures re-encoded losslessly, drawn only through the extension
// (required, no fallback), renders byte for byte the PNG scene's picture.
TEST_P(ExtensionImageSceneTest, ABoxSceneRendersThePictureOfItsPngTwin) {
  const Format& format = GetParam();
  const fs::path png = input("png/scene.gltf");
  test_support::writeBoxScene(png, {.format = builder::FileFormat::GltfEmbedded});
  const fs::path twin = test_support::withTexturesThrough(
      png, input("twin"), format.extension, format.suffix, [&](const Image& image) {
        return format.encode(image.width, image.height, image.rgba, Coding::Lossless);
      });
  const std::vector<std::string> size = {"--width", "96", "--height", "64"};
  const Run fromPng = runSucceeding("render", {png.string(), "-o", "png.png"}, size);
  const Run fromTwin = runSucceeding("render", {twin.string(), "-o", "twin.png"}, size);
  EXPECT_EQ(fromTwin.err, "") << "no warning for a valid file";
  EXPECT_TRUE(test_support::sameBytes(output("png.png"), output("twin.png")));
}

// Every error path ends the same way: one line naming the file and the image, exit status 2,
// and no picture written.
TEST_P(ExtensionImageSceneTest, ADamagedImageEndsTheRenderWithStatusTwoAndNoPicture) {
  const Format& format = GetParam();
  std::vector<unsigned char> bytes =
      format.encode(16, 16, test_support::cornersPictureRgba(16, 16), Coding::Lossy);
  bytes.resize(bytes.size() / 2);
  const fs::path path =
      test_support::writeTexturedTriangle(in_, {format.image(bytes)}, ImageStorage::DataUri);
  const Run r = run({"render", path.string(), "-o", "broken.png"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(test_support::contains(r.err, path.string() + ": images[0]")) << r.err;
  EXPECT_FALSE(fs::exists(output("broken.png")));
}

std::string formatName(const ::testing::TestParamInfo<Format>& info) {
  return info.param.name;
}
INSTANTIATE_TEST_SUITE_P(Formats, ExtensionImageTest, ::testing::ValuesIn(kFormats), formatName);
INSTANTIATE_TEST_SUITE_P(Formats, ExtensionImageSceneTest, ::testing::ValuesIn(kFormats),
                         formatName);

// ---- WebP

builder::MeshData triangle() {
  builder::MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals.assign(3, glm::vec3(0, 0, 1));
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  return mesh;
}

// A scene of one triangle whose texture has a 1x1 green PNG as its core source; each call adds
// an image (in a bufferView) that the texture names through `extension`.
struct TextureWithFallback {
  builder::GltfBuilder builder;
  TextureWithFallback() {
    const int texture = builder.addTexture(1, 1, {0, 255, 0, 255}, "fallback");
    builder.addNode("triangle", {}, builder.addTexturedMesh(triangle(), texture));
  }
  void add(const char* extension, const std::vector<unsigned char>& bytes, const char* mimeType) {
    tinygltf::Model& model = builder.model();
    tinygltf::Image image;
    image.mimeType = mimeType;
    image.bufferView = builder::appendBufferView(model, bytes, 0, 0);
    model.images.push_back(image);
    model.textures[0].extensions[extension] = tinygltf::Value(tinygltf::Value::Object{
        {"source", tinygltf::Value(static_cast<int>(model.images.size()) - 1)}});
    model.extensionsUsed.push_back(extension);
  }
  Scene load(const TempFolder& folder) {
    const fs::path path = folder.path() / "scene.glb";
    builder.write(path, builder::FileFormat::Glb);
    return loadGltf(path);
  }
};

test_support::SceneImage webpImage(std::vector<unsigned char> bytes) {
  return {std::move(bytes), "tex", "image/webp", "tex.webp", kWebp};
}

// The specification's example: a core PNG source for other viewers and the WebP for those that
// decode it. The WebP is drawn, and the PNG, which nothing else draws, is not decoded.
TEST(WebpImage, TheWebpIsDrawnAndItsPngFallbackIsNotDecoded) {
  TempFolder folder("webp");
  TextureWithFallback file;
  const std::vector<std::uint8_t> red = {255, 0, 0, 255, 255, 0, 0, 128};
  file.add(kWebp, encodeWebp(2, 1, red, Coding::Lossless), "image/webp");
  const Scene scene = file.load(folder);
  ASSERT_EQ(scene.images.size(), 2u);
  EXPECT_EQ(scene.textures.at(0).image, 1);
  EXPECT_TRUE(scene.images[0].rgba.empty());
  EXPECT_EQ(scene.images[0].format, "");
  EXPECT_EQ(scene.images[1].rgba, red);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
}

TEST(WebpImage, AFileThatIsNoWebpAfterItsRiffHeaderIsRefusedNamingTheImage) {
  std::vector<unsigned char> noise = {'R', 'I', 'F', 'F', 40,  0,   0,  0, 'W', 'E',
                                      'B', 'P', 'V', 'P', '8', ' ', 28, 0, 0,   0};
  noise.resize(48, 0x5A);
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(folder.path(), {webpImage(noise)},
                                                            ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"tex\": no WebP header that can be decoded: damaged data (a "
                "bitstream error)");
}

// The extended format's header (VP8X) with the animation flag: EXT_texture_webp takes stills.
TEST(WebpImage, AnAnimatedWebpIsRefusedNamingTheImage) {
  std::vector<unsigned char> animated = {'R',  'I', 'F', 'F', 22,  0,   0,  0,  'W', 'E',
                                         'B',  'P', 'V', 'P', '8', 'X', 10, 0,  0,   0,
                                         0x02, 0,   0,   0,   15,  0,   0,  15, 0,   0};
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(folder.path(), {webpImage(animated)},
                                                            ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"tex\": an animated WebP (EXT_texture_webp takes still images)");
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
TEST(WebpImage, AHeaderClaimingHalfAGigabyteOverAFewBytesIsRefusedWithoutTouchingIt) {
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(
      folder.path(), {webpImage(losslessClaim(11585))}, ImageStorage::BufferView);
  const long before = peakResidentKiB();
  const std::string error = inputError([&] { loadGltf(path); });
  EXPECT_EQ(error.rfind(path.string() + ": images[0] \"tex\": cannot decode the WebP: ", 0), 0u)
      << error;
  EXPECT_LT(peakResidentKiB() - before, 128 * 1024) << "KiB more at the peak";
}

// libwebp's lossless decoder holds the picture twice: WebP's limit is half the texels of the
// other formats', checked from the header.
TEST(WebpImage, AWebpLargerThanTheWebpLimitIsRefusedFromItsHeader) {
  TempFolder folder("webp");
  const fs::path path = test_support::writeTexturedTriangle(
      folder.path(), {webpImage(losslessClaim(16383))}, ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"tex\": 16383x16383 texels is too large (at most 32768 per side "
                "and 134217728 in all for WebP)");
}

// ---- AVIF

// gltf-transform writes AVIF without a fallback; a file may still offer a PNG one, and a WebP
// too: the AVIF is drawn, and the images only the others reach are not decoded (the WebP here
// is no WebP at all: decoding it would fail the load).
TEST(AvifImage, TheAvifIsDrawnAndTheTexturesOtherImagesAreNotDecoded) {
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(8, 4);
  TempFolder folder("avif");
  TextureWithFallback file;
  file.add(kAvif, encodeAvif(8, 4, source, Coding::Lossless), "image/avif");
  file.add(kWebp, {'R', 'I', 'F', 'F', 4, 0, 0, 0, 'W', 'E', 'B', 'P'}, "image/webp");
  const Scene scene = file.load(folder);
  ASSERT_EQ(scene.images.size(), 3u);
  EXPECT_EQ(scene.textures.at(0).image, 1);
  EXPECT_TRUE(scene.images[0].rgba.empty());
  EXPECT_EQ(scene.images[1].rgba, source);
  EXPECT_TRUE(scene.images[2].rgba.empty());
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
}

// Several frames make an image sequence (brand avis): EXT_texture_avif takes stills.
TEST(AvifImage, AnAvifImageSequenceIsRefusedNamingTheImage) {
  const std::vector<unsigned char> sequence =
      encodeAvif(16, 16, test_support::cornersPictureRgba(16, 16), Coding::Lossy, 2);
  TempFolder folder("avif");
  const fs::path path = test_support::writeTexturedTriangle(
      folder.path(), {{sequence, "tex", "image/avif", "tex.avif", kAvif}},
      ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"tex\": an AVIF image sequence (EXT_texture_avif "
                "takes still images)");
}

// libavif takes the container's size (its ispe box) over the AV1 frame's: 8x8 of AV1 data
// under an ispe of 16384^2 would decode to 16384^2, 1.4 GB with the planes. AVIF's limit is
// half the other formats' texels, checked from the container.
TEST(AvifImage, AContainerClaimingMoreThanTheLimitIsRefusedFromItsHeader) {
  std::vector<unsigned char> avif =
      encodeAvif(8, 8, test_support::cornersPictureRgba(8, 8), Coding::Lossy);
  const std::string ispe = "ispe";
  const auto at = std::search(avif.begin(), avif.end(), ispe.begin(), ispe.end());
  ASSERT_NE(at, avif.end());
  // After the type, version and flags (4 bytes): width and height, big-endian.
  const std::size_t size = static_cast<std::size_t>(at - avif.begin()) + 8;
  for (std::size_t field : {size, size + 4})
    for (int i = 0; i < 4; ++i)
      avif[field + i] = static_cast<unsigned char>(16384u >> (24 - 8 * i));
  TempFolder folder("avif");
  const fs::path path = test_support::writeTexturedTriangle(
      folder.path(), {{avif, "tex", "image/avif", "tex.avif", kAvif}}, ImageStorage::BufferView);
  EXPECT_EQ(inputError([&] { loadGltf(path); }),
            path.string() +
                ": images[0] \"tex\": 16384x16384 texels is too large (at most 32768 per side "
                "and 134217728 in all for AVIF)");
}

class AvifLoadingTest : public test_support::CliFixture {
 protected:
  AvifLoadingTest() : CliFixture("avif-loading") {}
};

// libavif brings the AV1 codecs: a run loads it only for a scene with an AVIF image.
TEST_F(AvifLoadingTest, LibavifIsLoadedOnlyForAScenesAvifImages) {
  const std::vector<std::uint8_t> source = test_support::cornersPictureRgba(4, 4);
  const auto inspect = [&](const test_support::SceneImage& image, const std::string& stem) {
    const fs::path scene =
        test_support::writeTexturedTriangle(in_, {image}, ImageStorage::File, stem);
    return run({"info", scene.string()}, {"LD_DEBUG=files"});
  };
  const Run withWebp = inspect(webpImage(encodeWebp(4, 4, source, Coding::Lossless)), "webp");
  ASSERT_EQ(withWebp.status, 0) << withWebp.err;
  EXPECT_NE(withWebp.err.find("libwebp"), std::string::npos) << "LD_DEBUG gave no list";
  EXPECT_EQ(withWebp.err.find("libavif"), std::string::npos);
  const Run withAvif = inspect(
      {encodeAvif(4, 4, source, Coding::Lossless), "tex", "image/avif", "tex.avif", kAvif}, "avif");
  ASSERT_EQ(withAvif.status, 0) << withAvif.err;
  EXPECT_NE(withAvif.err.find("libavif"), std::string::npos);
}

}  // namespace
}  // namespace omnishadow::extension_images_test
