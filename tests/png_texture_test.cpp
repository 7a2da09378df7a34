// PNG textures: the common ones (8-bit RGB or RGBA, not interlaced) decoded with libdeflate
// (renderer/scene/png_texture_decoder.cpp), every other PNG left to stb_image, which decoded
// them all before. The PNGs are made here from known pixels, with each row filter; the real
// ones are the repository's scenes.
#include <gtest/gtest.h>
#include <libdeflate.h>
#include <sys/resource.h>
#include <tiny_gltf.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/png_texture_decoder.h"
#include "tests/support/input_error.h"
#include "tests/support/temp_folder.h"
#include "tests/support/textured_triangle.h"

namespace omnishadow::png_texture_test {
namespace {

using gltf_detail::DecodedPng;
using gltf_detail::decodePngTexture;
using test_support::TempFolder;
namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

constexpr std::uint32_t kMaxSide = 32768;
constexpr std::uint64_t kMaxTexels = std::uint64_t{1} << 28;

void put32(Bytes& out, std::uint32_t v) {
  out.insert(out.end(), {static_cast<std::uint8_t>(v >> 24), static_cast<std::uint8_t>(v >> 16),
                         static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v)});
}

void chunk(Bytes& png, const std::string& type, const Bytes& data) {
  put32(png, static_cast<std::uint32_t>(data.size()));
  Bytes typed(type.begin(), type.end());
  typed.insert(typed.end(), data.begin(), data.end());
  png.insert(png.end(), typed.begin(), typed.end());
  put32(png, libdeflate_crc32(0, typed.data(), typed.size()));
}

Bytes zlib(const Bytes& raw) {
  libdeflate_compressor* compressor = libdeflate_alloc_compressor(6);
  Bytes out(libdeflate_zlib_compress_bound(compressor, raw.size()));
  out.resize(libdeflate_zlib_compress(compressor, raw.data(), raw.size(), out.data(), out.size()));
  libdeflate_free_compressor(compressor);
  EXPECT_FALSE(out.empty());
  return out;
}

// PNG's predictors (section 9.4), from the left (a), upper (b) and upper-left (c) bytes.
int predictor(int filter, int a, int b, int c) {
  switch (filter) {
    case 1:
      return a;
    case 2:
      return b;
    case 3:
      return (a + b) / 2;
    case 4: {
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
    }
    default:
      return 0;
  }
}

// The rows of `pixels` (bpp bytes a pixel), each filtered with filters[row % size], as the
// zlib stream of a PNG holds them: a filter byte, then the row.
Bytes filterRows(const Bytes& pixels, int width, int height, int bpp,
                 const std::vector<int>& filters) {
  const auto stride = static_cast<std::size_t>(width * bpp);
  Bytes raw;
  for (int y = 0; y < height; ++y) {
    const int filter = filters[static_cast<std::size_t>(y) % filters.size()];
    raw.push_back(static_cast<std::uint8_t>(filter));
    const std::uint8_t* row = pixels.data() + static_cast<std::size_t>(y) * stride;
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= static_cast<std::size_t>(bpp) ? row[i - bpp] : 0;
      const int b = y > 0 ? row[i - stride] : 0;
      const int c = y > 0 && i >= static_cast<std::size_t>(bpp) ? row[i - stride - bpp] : 0;
      raw.push_back(static_cast<std::uint8_t>(row[i] - predictor(filter, a, b, c)));
    }
  }
  return raw;
}

struct PngLayout {
  int bitDepth = 8;
  int colorType = 6;  // 2 RGB, 6 RGBA, 0 grey, 4 grey + alpha, 3 palette
  int interlace = 0;
  int dataChunks = 1;  // the zlib stream split over this many IDAT chunks
  std::vector<std::pair<std::string, Bytes>> before, after;  // chunks around the IDATs
};

Bytes pngFile(int width, int height, const Bytes& stream, const PngLayout& layout) {
  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  Bytes header;
  put32(header, static_cast<std::uint32_t>(width));
  put32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {static_cast<std::uint8_t>(layout.bitDepth),
                               static_cast<std::uint8_t>(layout.colorType), 0, 0,
                               static_cast<std::uint8_t>(layout.interlace)});
  chunk(png, "IHDR", header);
  for (const auto& [type, data] : layout.before) chunk(png, type, data);
  const std::size_t piece = stream.size() / static_cast<std::size_t>(layout.dataChunks) + 1;
  for (std::size_t at = 0; at < stream.size(); at += piece)
    chunk(png, "IDAT",
          Bytes(stream.begin() + static_cast<std::ptrdiff_t>(at),
                stream.begin() + static_cast<std::ptrdiff_t>(std::min(stream.size(), at + piece))));
  for (const auto& [type, data] : layout.after) chunk(png, type, data);
  chunk(png, "IEND", {});
  return png;
}

Bytes randomPixels(std::size_t count, unsigned seed) {
  std::mt19937 random(seed);
  Bytes pixels(count);
  for (std::uint8_t& v : pixels) v = static_cast<std::uint8_t>(random() >> 24);
  return pixels;
}

Bytes toRgba(const Bytes& pixels, int channels) {
  if (channels == 4) return pixels;
  Bytes rgba;
  for (std::size_t i = 0; i < pixels.size(); i += 3)
    rgba.insert(rgba.end(), {pixels[i], pixels[i + 1], pixels[i + 2], 255});
  return rgba;
}

// What stb_image, through tinygltf as the loader called it before, makes of `png`.
tinygltf::Image stbDecode(const Bytes& png, bool& decoded) {
  tinygltf::Image image;
  std::string error, warning;
  decoded = tinygltf::LoadImageData(&image, 0, &error, &warning, 0, 0, png.data(),
                                    static_cast<int>(png.size()), nullptr);
  return image;
}

// A scene of one triangle textured with `png`, in a .glb's bufferView or in a file beside a
// .gltf (the loader decodes both, several at a time).
fs::path sceneWithPng(const TempFolder& folder, const Bytes& png, bool inFile) {
  return test_support::writeTexturedTriangle(
      folder.path(), {{png, "picture", "image/png", "picture.png", ""}},
      inFile ? test_support::ImageStorage::File : test_support::ImageStorage::BufferView);
}

// Every filter in every position (the first row has no row above, the first pixel nothing to
// its left), with RGB and RGBA, on widths and heights down to one pixel (the rows are unfiltered
// in the buffer they were inflated into, where a one-pixel-wide RGB row leaves no slack): the
// source pixels, byte for byte, and what stb_image decodes.
TEST(PngTexture, EveryRowFilterGivesTheSourcePixels) {
  const std::vector<std::vector<int>> orders = {{0, 1, 2, 3, 4}, {4, 3, 2, 1, 0}, {2, 4, 3, 1}};
  unsigned seed = 1;
  for (int channels : {3, 4})
    for (int width : {1, 2, 5, 33})
      for (int height : {1, 2, 11})
        for (const std::vector<int>& filters : orders) {
          const Bytes pixels =
              randomPixels(static_cast<std::size_t>(width * height * channels), seed++);
          PngLayout layout;
          layout.colorType = channels == 4 ? 6 : 2;
          const Bytes png = pngFile(
              width, height, zlib(filterRows(pixels, width, height, channels, filters)), layout);
          SCOPED_TRACE("channels " + std::to_string(channels) + ", " + std::to_string(width) + "x" +
                       std::to_string(height) + ", first filter " + std::to_string(filters[0]));
          const DecodedPng decoded = decodePngTexture(png.data(), png.size(), kMaxSide, kMaxTexels);
          ASSERT_TRUE(decoded.ok);
          EXPECT_EQ(decoded.width, width);
          EXPECT_EQ(decoded.height, height);
          EXPECT_EQ(decoded.rgba, toRgba(pixels, channels));
          bool stbDecoded = false;
          const tinygltf::Image stb = stbDecode(png, stbDecoded);
          ASSERT_TRUE(stbDecoded);
          EXPECT_EQ(decoded.rgba, stb.image);
        }
}

// Paeth's ties (equal distances pick left, then up) and the average's rounding, where random
// pixels seldom land: flat areas, steps of one and wrap-arounds past 255.
TEST(PngTexture, PaethTiesAndAverageRoundingFollowTheStandard) {
  constexpr int kWidth = 16, kHeight = 16;
  Bytes pixels;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const int v = (x / 4) * 85 + (y % 3) - (x % 2) * 2;
      pixels.insert(pixels.end(), {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(255 - v),
                                   static_cast<std::uint8_t>(x == y ? 255 : 0),
                                   static_cast<std::uint8_t>(y * 17)});
    }
  for (int filter : {3, 4}) {
    const Bytes png =
        pngFile(kWidth, kHeight, zlib(filterRows(pixels, kWidth, kHeight, 4, {filter})), {});
    const DecodedPng decoded = decodePngTexture(png.data(), png.size(), kMaxSide, kMaxTexels);
    ASSERT_TRUE(decoded.ok);
    EXPECT_EQ(decoded.rgba, pixels) << "filter " << filter;
  }
}

// The zlib stream may be split over several IDAT chunks, and ancillary chunks (text, gamma,
// colour space, time) stand around them: the picture is the same.
TEST(PngTexture, ImageDataInSeveralChunksAmongAncillaryOnes) {
  constexpr int kWidth = 40, kHeight = 30;
  const Bytes pixels = randomPixels(kWidth * kHeight * 3, 7);
  const Bytes stream = zlib(filterRows(pixels, kWidth, kHeight, 3, {1, 2, 3, 4}));
  PngLayout layout;
  layout.colorType = 2;
  layout.dataChunks = 5;
  layout.before = {{"tEXt", {'k', 0, 'v'}}, {"gAMA", {0, 0, 0xB1, 0x8F}}, {"sRGB", {0}}};
  layout.after = {{"tIME", {0x07, 0xEA, 11, 27, 12, 0, 0}}};
  const Bytes png = pngFile(kWidth, kHeight, stream, layout);
  const DecodedPng decoded = decodePngTexture(png.data(), png.size(), kMaxSide, kMaxTexels);
  ASSERT_TRUE(decoded.ok);
  EXPECT_EQ(decoded.rgba, toRgba(pixels, 3));
}

// Through the loader, from a .glb's bufferView and from a file of its own: the image is the
// decoded picture, with no warning.
TEST(PngTexture, TheLoaderDecodesBufferViewAndFileImagesAlike) {
  constexpr int kWidth = 24, kHeight = 20;
  const Bytes pixels = randomPixels(kWidth * kHeight * 4, 11);
  const Bytes png =
      pngFile(kWidth, kHeight, zlib(filterRows(pixels, kWidth, kHeight, 4, {0, 1, 2, 3, 4})), {});
  for (bool inFile : {false, true}) {
    TempFolder folder("png");
    const Scene scene = loadGltf(sceneWithPng(folder, png, inFile));
    ASSERT_EQ(scene.images.size(), 1u);
    EXPECT_EQ(scene.images[0].width, kWidth);
    EXPECT_EQ(scene.images[0].height, kHeight);
    EXPECT_EQ(scene.images[0].rgba, pixels) << (inFile ? "file" : "bufferView");
    EXPECT_TRUE(scene.warnings.empty());
  }
}

// The files this decoder leaves to stb_image, each of which stb_image decodes: through the
// loader the image is still stb_image's picture.
TEST(PngTexture, OtherKindsOfPngAreLeftToStbImage) {
  constexpr int kWidth = 9, kHeight = 7;
  struct Case {
    std::string name;
    Bytes png;
  };
  std::vector<Case> cases;
  const auto add = [&](const std::string& name, int channels, int colorType, int bitDepth,
                       const std::vector<std::pair<std::string, Bytes>>& before) {
    const int bytesPerPixel = channels * bitDepth / 8;
    const Bytes pixels =
        randomPixels(static_cast<std::size_t>(kWidth * kHeight * bytesPerPixel), 100 + channels);
    PngLayout layout;
    layout.colorType = colorType;
    layout.bitDepth = bitDepth;
    layout.before = before;
    cases.push_back(
        {name, pngFile(kWidth, kHeight,
                       zlib(filterRows(pixels, kWidth, kHeight, bytesPerPixel, {1, 4})), layout)});
  };
  add("grey", 1, 0, 8, {});
  add("grey and alpha", 2, 4, 8, {});
  add("16-bit RGBA", 4, 6, 16, {});
  add("RGB with a transparent colour", 3, 2, 8, {{"tRNS", {0, 10, 0, 20, 0, 30}}});
  Bytes palette;
  for (int i = 0; i < 256; ++i)
    palette.insert(palette.end(), {static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(255 - i),
                                   static_cast<std::uint8_t>(i / 2)});
  add("palette", 1, 3, 8, {{"PLTE", palette}});
  {
    // The Adler-32 at the stream's end is wrong: libdeflate refuses it, stb_image does not look.
    const Bytes pixels = randomPixels(kWidth * kHeight * 4, 5);
    Bytes stream = zlib(filterRows(pixels, kWidth, kHeight, 4, {2}));
    stream.back() ^= 0x55;
    cases.push_back({"a wrong checksum", pngFile(kWidth, kHeight, stream, {})});
  }
  {
    // More bytes than the rows take (stb_image reads what it needs and ignores the rest).
    Bytes raw = filterRows(randomPixels(kWidth * kHeight * 4, 6), kWidth, kHeight, 4, {0});
    raw.resize(raw.size() + 50, 0);
    cases.push_back({"extra bytes", pngFile(kWidth, kHeight, zlib(raw), {})});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    EXPECT_FALSE(decodePngTexture(c.png.data(), c.png.size(), kMaxSide, kMaxTexels).ok);
    bool stbDecoded = false;
    const tinygltf::Image stb = stbDecode(c.png, stbDecoded);
    ASSERT_TRUE(stbDecoded);
    TempFolder folder("png");
    const Scene scene = loadGltf(sceneWithPng(folder, c.png, false));
    ASSERT_EQ(scene.images.size(), 1u);
    EXPECT_EQ(scene.images[0].width, kWidth);
    if (stb.bits == 8 && stb.component == 4) {
      EXPECT_EQ(scene.images[0].rgba, stb.image);
    } else {
      EXPECT_EQ(scene.images[0].rgba.size(), std::size_t{kWidth * kHeight * 4});
    }
  }
}

// Damaged files the decoder gives up on go to stb_image too, which fails on them as it did:
// the load fails naming the image. Also refused here: interlaced files, and frames beyond the
// limits it is given (the loader's are checked before any decoder runs).
TEST(PngTexture, DamagedInterlacedAndOversizedFilesAreNotDecodedHere) {
  constexpr int kWidth = 8, kHeight = 8;
  const Bytes pixels = randomPixels(kWidth * kHeight * 4, 9);
  Bytes raw = filterRows(pixels, kWidth, kHeight, 4, {0});
  raw[0] = 5;  // no such filter
  const Bytes badFilter = pngFile(kWidth, kHeight, zlib(raw), {});
  raw.resize(raw.size() / 2);
  const Bytes tooFewBytes = pngFile(kWidth, kHeight, zlib(raw), {});
  Bytes noEnd = pngFile(kWidth, kHeight, zlib(filterRows(pixels, kWidth, kHeight, 4, {0})), {});
  noEnd.resize(noEnd.size() - 12);
  PngLayout interlaced;
  interlaced.interlace = 1;
  const Bytes adam7 =
      pngFile(kWidth, kHeight, zlib(filterRows(pixels, kWidth, kHeight, 4, {0})), interlaced);
  for (const Bytes* png :
       std::initializer_list<const Bytes*>{&badFilter, &tooFewBytes, &noEnd, &adam7})
    EXPECT_FALSE(decodePngTexture(png->data(), png->size(), kMaxSide, kMaxTexels).ok);
  for (const Bytes* png : std::initializer_list<const Bytes*>{&badFilter, &tooFewBytes}) {
    bool stbDecoded = true;
    stbDecode(*png, stbDecoded);
    EXPECT_FALSE(stbDecoded);
    TempFolder folder("png");
    const fs::path scene = sceneWithPng(folder, *png, false);
    const std::string message = test_support::inputError([&] { loadGltf(scene); });
    EXPECT_NE(message.find("images[0] \"picture\""), std::string::npos) << message;
  }
  const Bytes fine =
      pngFile(kWidth, kHeight, zlib(filterRows(pixels, kWidth, kHeight, 4, {0})), {});
  EXPECT_TRUE(decodePngTexture(fine.data(), fine.size(), kMaxSide, kMaxTexels).ok);
  EXPECT_FALSE(decodePngTexture(fine.data(), fine.size(), kWidth - 1, kMaxTexels).ok);
  EXPECT_FALSE(decodePngTexture(fine.data(), fine.size(), kMaxSide, kWidth * kHeight - 1).ok);
  EXPECT_FALSE(decodePngTexture(fine.data(), 20, kMaxSide, kMaxTexels).ok);
}

// A file's images are decoded several at a time, PNGs this decoder takes beside ones it leaves
// to stb_image (palettes here), from bufferViews and from files of their own: each image gets
// its own pixels.
TEST(PngTexture, ImagesDecodedTogetherKeepTheirOwnPixels) {
  constexpr int kHeight = 13;
  std::vector<test_support::SceneImage> files;
  std::vector<Bytes> expected;
  for (int i = 0; i < 8; ++i) {
    const int width = 17 + 3 * i;
    const std::string name = "picture" + std::to_string(i);
    if (i % 3 == 2) {  // an 8-bit palette of grey levels: stb_image's
      const Bytes indices = randomPixels(static_cast<std::size_t>(width * kHeight), 200 + i);
      Bytes palette, rgba;
      for (int v = 0; v < 256; ++v)
        palette.insert(palette.end(), {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v),
                                       static_cast<std::uint8_t>(v)});
      for (std::uint8_t index : indices) rgba.insert(rgba.end(), {index, index, index, 255});
      PngLayout layout;
      layout.colorType = 3;
      layout.before = {{"PLTE", palette}};
      files.push_back(
          {pngFile(width, kHeight, zlib(filterRows(indices, width, kHeight, 1, {1, 4})), layout),
           name, "image/png", name + ".png", ""});
      expected.push_back(rgba);
    } else {
      const int channels = i % 2 == 0 ? 4 : 3;
      const Bytes pixels =
          randomPixels(static_cast<std::size_t>(width * kHeight * channels), 300 + i);
      PngLayout layout;
      layout.colorType = channels == 4 ? 6 : 2;
      files.push_back(
          {pngFile(width, kHeight, zlib(filterRows(pixels, width, kHeight, channels, {3, 4, 2})),
                   layout),
           name, "image/png", name + ".png", ""});
      expected.push_back(toRgba(pixels, channels));
    }
  }
  for (test_support::ImageStorage storage :
       {test_support::ImageStorage::BufferView, test_support::ImageStorage::File}) {
    TempFolder folder("png");
    const Scene scene =
        loadGltf(test_support::writeTexturedTriangle(folder.path(), files, storage));
    ASSERT_EQ(scene.images.size(), files.size());
    for (std::size_t i = 0; i < files.size(); ++i) {
      SCOPED_TRACE(i);
      EXPECT_EQ(scene.images[i].rgba, expected[i]);
    }
  }
}

// A few bytes of data claiming the largest picture the limits allow (16384^2 RGBA, 1 GiB) are
// refused before the picture's buffer is made: DEFLATE cannot expand them that far. Through the
// loader too, in a file padded with a text chunk past the loader's own bound (rows per byte of
// file): the load fails naming the image, as stb_image failed on it. The process's peak
// resident memory shows whether a gigabyte was touched (zeroed) on the way.
TEST(PngTexture, AFewBytesClaimingAHugePictureTouchNoMemory) {
  constexpr int kSide = 16384;
  const Bytes stream = zlib(Bytes(4096, 0));
  const auto peakKiB = [] {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
  };
  const long before = peakKiB();
  const Bytes png = pngFile(kSide, kSide, stream, {});
  EXPECT_FALSE(decodePngTexture(png.data(), png.size(), kMaxSide, kMaxTexels).ok);

  PngLayout padded;
  Bytes text = {'k', 0};
  text.resize(std::size_t{kSide} * kSide * 4 / gltf_detail::kMaxDeflateExpansion + kSide, 'x');
  padded.before = {{"tEXt", text}};
  TempFolder folder("png");
  const fs::path scene = sceneWithPng(folder, pngFile(kSide, kSide, stream, padded), true);
  const std::string message = test_support::inputError([&] { loadGltf(scene); });
  EXPECT_NE(message.find("images[0] \"picture\""), std::string::npos) << message;
  EXPECT_LT(peakKiB() - before, 256 * 1024) << "KiB more at the peak";
}

// Real textures nobody here made (the repository's Khronos and compressed scenes): those this
// decoder takes give stb_image's picture byte for byte; the others (Duck's palette) it leaves.
TEST(PngTexture, RealTexturesDecodeAsStbImageDecodesThem) {
  int taken = 0, left = 0;
  for (const auto& entry :
       fs::recursive_directory_iterator(fs::path(OMNISHADOW_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".png") continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const Bytes png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    SCOPED_TRACE(entry.path().string());
    bool stbDecoded = false;
    const tinygltf::Image stb = stbDecode(png, stbDecoded);
    ASSERT_TRUE(stbDecoded);
    const DecodedPng decoded = decodePngTexture(png.data(), png.size(), kMaxSide, kMaxTexels);
    if (!decoded.ok) {
      ++left;
      continue;
    }
    ++taken;
    EXPECT_EQ(decoded.width, stb.width);
    EXPECT_EQ(decoded.height, stb.height);
    EXPECT_EQ(decoded.rgba, stb.image);
  }
  EXPECT_GE(taken, 5);
  EXPECT_GE(left, 1);
}

}  // namespace
}  // namespace omnishadow::png_texture_test
