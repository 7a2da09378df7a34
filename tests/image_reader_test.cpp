// readImage without OpenImageIO for PNG and EXR must read exactly what OpenImageIO read before
// (values, channel names, channel order), and reach every other format through the plugin.
// OpenImageIO is linked here as the reference; the PNG files come from libpng directly, so that
// every colour type, bit depth, palette and interlacing is covered.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/output/exr_reader.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/png_encoder.h"
#include "tests/support/run_binary.h"
#include "tests/support/temp_folder.h"

namespace omnishadow::image_reader_test {
namespace {

namespace fs = std::filesystem;

struct TempDir : test_support::TempFolder {
  TempDir() : TempFolder("omnishadow-reader") {}
};

// What OpenImageIO 2.4 returns for the file, the way readImage called it until 0.2.
FloatImage readWithOiio(const fs::path& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(path.string(), &config);
  EXPECT_TRUE(input) << OIIO::geterror();
  FloatImage image;
  if (!input) return image;
  const OIIO::ImageSpec& spec = input->spec();
  image.width = spec.width;
  image.height = spec.height;
  image.channels.assign(spec.channelnames.begin(), spec.channelnames.end());
  image.pixels.resize(std::size_t(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(
      input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()));
  return image;
}

void expectIdentical(const FloatImage& expected, const FloatImage& actual) {
  EXPECT_EQ(actual.width, expected.width);
  EXPECT_EQ(actual.height, expected.height);
  EXPECT_EQ(actual.channels, expected.channels);
  ASSERT_EQ(actual.pixels.size(), expected.pixels.size());
  for (std::size_t i = 0; i < expected.pixels.size(); ++i)
    ASSERT_EQ(actual.pixels[i], expected.pixels[i]) << "at " << i;
}

struct PngVariant {
  const char* name;
  int colorType, bitDepth;
  bool interlaced = false, transparency = false;
};

// gtest names the parameter by this instead of dumping its bytes (padding included).
void PrintTo(const PngVariant& variant, std::ostream* out) {
  *out << variant.name;
}

// A 13x7 PNG of `variant` written with libpng: samples cover the whole range of the bit depth;
// palettes have 16 entries; transparency adds a tRNS chunk.
void writeVariant(const fs::path& path, const PngVariant& v) {
  const int width = 13, height = 7;
  FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, v.bitDepth, v.colorType,
               v.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette;
  if (v.colorType == PNG_COLOR_TYPE_PALETTE) {
    for (int i = 0; i < 16; ++i)
      palette.push_back({png_byte(i * 16), png_byte(255 - i * 9), png_byte(i * 5)});
    png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
  }
  std::vector<png_byte> alphas = {0, 64, 128, 255, 7};
  png_color_16 key{};
  key.gray = 3;
  key.red = 0;
  key.green = 0;
  key.blue = 0;
  if (v.transparency)
    png_set_tRNS(png, info, alphas.data(), static_cast<int>(alphas.size()),
                 v.colorType == PNG_COLOR_TYPE_PALETTE ? nullptr : &key);
  png_write_info(png, info);
  if (v.bitDepth == 16) png_set_swap(png);
  const int channels = png_get_channels(png, info);
  const std::size_t rowBytes = png_get_rowbytes(png, info);
  std::vector<png_byte> data(rowBytes * height);
  const unsigned maxSample = v.colorType == PNG_COLOR_TYPE_PALETTE ? 15 : (1u << v.bitDepth) - 1;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width * channels; ++x) {
      const unsigned sample = (unsigned(y) * 977 + unsigned(x) * 131) % (maxSample + 1);
      png_byte* row = data.data() + y * rowBytes;
      if (v.bitDepth == 16) {
        row[2 * x] = png_byte(sample & 0xff);
        row[2 * x + 1] = png_byte(sample >> 8);
      } else if (v.bitDepth == 8) {
        row[x] = png_byte(sample);
      } else {
        const int perByte = 8 / v.bitDepth, shift = 8 - v.bitDepth * (x % perByte + 1);
        row[x / perByte] = png_byte(row[x / perByte] | (sample << shift));
      }
    }
  std::vector<png_bytep> rows;
  for (int y = 0; y < height; ++y) rows.push_back(data.data() + y * rowBytes);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

class PngVariantTest : public ::testing::TestWithParam<PngVariant> {};

TEST_P(PngVariantTest, ReadsExactlyWhatOpenImageIOReads) {
  TempDir dir;
  const fs::path path = dir / "v.png";
  writeVariant(path, GetParam());
  expectIdentical(readWithOiio(path), readImage(path));
}

INSTANTIATE_TEST_SUITE_P(
    Variants, PngVariantTest,
    ::testing::Values(
        PngVariant{"Grey1", PNG_COLOR_TYPE_GRAY, 1}, PngVariant{"Grey2", PNG_COLOR_TYPE_GRAY, 2},
        PngVariant{"Grey4", PNG_COLOR_TYPE_GRAY, 4}, PngVariant{"Grey8", PNG_COLOR_TYPE_GRAY, 8},
        PngVariant{"Grey16", PNG_COLOR_TYPE_GRAY, 16},
        PngVariant{"Grey8Key", PNG_COLOR_TYPE_GRAY, 8, false, true},
        PngVariant{"GreyAlpha8", PNG_COLOR_TYPE_GRAY_ALPHA, 8},
        PngVariant{"GreyAlpha16", PNG_COLOR_TYPE_GRAY_ALPHA, 16},
        PngVariant{"Rgb8", PNG_COLOR_TYPE_RGB, 8}, PngVariant{"Rgb16", PNG_COLOR_TYPE_RGB, 16},
        PngVariant{"Rgb8Interlaced", PNG_COLOR_TYPE_RGB, 8, true},
        PngVariant{"Rgba8", PNG_COLOR_TYPE_RGB_ALPHA, 8},
        PngVariant{"Rgba16Interlaced", PNG_COLOR_TYPE_RGB_ALPHA, 16, true},
        PngVariant{"Palette4", PNG_COLOR_TYPE_PALETTE, 4},
        PngVariant{"Palette8Alpha", PNG_COLOR_TYPE_PALETTE, 8, false, true}),
    [](const auto& variant) { return std::string(variant.param.name); });

TEST(ImageReaderTest, TruncatedPngIsAnInputErrorNamingTheFile) {
  TempDir dir;
  const std::vector<std::uint8_t> pixels(32 * 32 * 3, 77);
  const std::string png = encodePng(32, 32, 3, pixels);
  std::ofstream(dir / "cut.png", std::ios::binary) << png.substr(0, png.size() / 2);
  try {
    readImage(dir / "cut.png");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_TRUE(
        std::string(error.what()).starts_with((dir / "cut.png").string() + ": cannot read image: "))
        << error.what();
  }
}

// Channel sets as the renderer writes them (beauty, AOVs, depth) and the orders OpenImageIO
// gives special names: R,G,B before A, X,Y,Z in a position layer, Z after A, layers by name.
TEST(ImageReaderTest, ExrChannelsComeInOpenImageIOsOrderWithItsValues) {
  const std::vector<std::vector<std::string>> sets = {
      {"R", "G", "B", "A"},
      {"Z"},
      {"A", "B", "G", "R", "Z", "albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "P.X",
       "P.Y", "P.Z", "depth", "objectId", "visibility.lamp", "visibility.sun"},
      {"Y", "A", "Alpha", "foo", "Depth", "Zback", "real", "imag", "red", "x", "y", "RA"},
      {"layer.X", "layer.Y", "layer.R", "layer.A", "layer.w", "other.Y", "other.A"},
  };
  for (const auto& names : sets) {
    TempDir dir;
    FloatImage image{3, 2, names, {}};
    for (std::size_t i = 0; i < 6 * names.size(); ++i)
      image.pixels.push_back(0.25f * float(i) - 3.0f);
    writeExr(dir / "a.exr", image, ExrPixelType::Float);
    const FloatImage expected = readWithOiio(dir / "a.exr");
    SCOPED_TRACE(::testing::PrintToString(expected.channels));
    expectIdentical(expected, readImage(dir / "a.exr"));
  }
}

TEST(ImageReaderTest, OtherFormatsAreReadThroughTheOpenImageIOPlugin) {
  TempDir dir;
  const fs::path path = dir / "a.tif";
  const std::vector<float> values = {0.0f, 0.5f, 1.0f, 0.25f, 0.125f, 2.0f};
  auto output = OIIO::ImageOutput::create("tiff");
  ASSERT_TRUE(output);
  ASSERT_TRUE(output->open(path.string(), OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::FLOAT)));
  ASSERT_TRUE(output->write_image(OIIO::TypeDesc::FLOAT, values.data()));
  ASSERT_TRUE(output->close());
  const FloatImage image = readImage(path);
  EXPECT_EQ(image.width, 2);
  EXPECT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(std::vector<float>(image.pixels.begin(), image.pixels.end()), values);

  std::ofstream(dir / "junk.tif") << "neither PNG, EXR nor anything else";
  EXPECT_THROW(readImage(dir / "junk.tif"), InputError);
  try {
    readImage(dir / "missing.png");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              (dir / "missing.png").string() + ": cannot read image: no such file");
  }
}

// Radiance HDR files as OpenImageIO writes them (run-length encoded rows from 8 pixels wide, flat
// rows below): the values OpenImageIO reads back, but for the half step of the mantissa that
// Radiance (and Blender) add when reading, (m + 0.5) 2^(e - 136), which OpenImageIO leaves out.
TEST(ImageReaderTest, RadianceHdrReadsWhatOpenImageIOReadsToHalfAMantissaStep) {
  TempDir dir;
  for (const auto& [width, height] : {std::pair{64, 5}, std::pair{5, 3}}) {
    SCOPED_TRACE(std::to_string(width) + " x " + std::to_string(height));
    std::vector<float> values(static_cast<std::size_t>(width) * height * 3);
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] = (i % 7 == 0) ? 0.0f
                               : std::ldexp(static_cast<float>((i * 37) % 101) + 1.0f,
                                            static_cast<int>(i % 23) - 12);
    const fs::path path = dir / ("a" + std::to_string(width) + ".hdr");
    auto output = OIIO::ImageOutput::create("hdr");
    ASSERT_TRUE(output);
    ASSERT_TRUE(
        output->open(path.string(), OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(output->write_image(OIIO::TypeDesc::FLOAT, values.data()));
    ASSERT_TRUE(output->close());
    const FloatImage expected = readWithOiio(path);
    const FloatImage image = readImage(path);
    ASSERT_EQ(image.width, width);
    ASSERT_EQ(image.height, height);
    EXPECT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
    for (std::size_t p = 0; p < values.size() / 3; ++p) {
      const float brightest = std::max({values[p * 3], values[p * 3 + 1], values[p * 3 + 2]});
      for (std::size_t c = 0; c < 3; ++c) {
        const float got = image.pixels[p * 3 + c], read = expected.pixels[p * 3 + c];
        EXPECT_GE(got, read) << p << " " << c;
        EXPECT_LE(got - read, brightest / 256.0f + 1e-30f) << p << " " << c;
        EXPECT_NEAR(got, values[p * 3 + c], brightest / 64.0f) << p << " " << c;
      }
    }
  }
}

// A run-length encoded row by hand: runs and literals, every exponent case, bottom-up rows.
TEST(ImageReaderTest, RadianceHdrRunsLiteralsAndRowOrder) {
  TempDir dir;
  const auto header = [](const std::string& resolution) {
    return std::string("#?RADIANCE\n# made by hand\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=2\n\n") +
           resolution + "\n";
  };
  // Row 0: R a run of 8 x 128, G literals 0..7 x 16, B runs of 4 x 64 and 4 x 0, E a run of
  // 8 x 129; row 1: flat pixels (one of each exponent case), then a zero exponent.
  std::string rle("\x02\x02\x00\x08", 4);
  rle += std::string("\x88\x80");
  rle += std::string("\x08") + std::string("\x00\x10\x20\x30\x40\x50\x60\x70", 8);
  rle += std::string("\x84\x40\x84\x00", 4);
  rle += std::string("\x88\x81");
  std::string flat;
  for (int x = 0; x < 8; ++x)
    flat += std::string(x == 7 ? "\x80\x80\x80\x00" : "\x80\x40\x20\x88", 4);
  const auto write = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return dir / name;
  };
  const FloatImage down = readImage(write("down.hdr", header("-Y 2 +X 8") + rle + flat));
  const FloatImage up = readImage(write("up.hdr", header("+Y 2 +X 8") + rle + flat));
  const auto at = [](const FloatImage& image, int x, int y, int c) { return image.at(x, y, c); };
  for (int x = 0; x < 8; ++x) {
    EXPECT_EQ(at(down, x, 0, 0), 128.5f / 128.0f);
    EXPECT_EQ(at(down, x, 0, 1), (16.0f * x + 0.5f) / 128.0f);
    EXPECT_EQ(at(down, x, 0, 2), x < 4 ? 64.5f / 128.0f : 0.5f / 128.0f);
    EXPECT_EQ(at(down, x, 1, 0), x == 7 ? 0.0f : 128.5f);
    EXPECT_EQ(at(down, x, 1, 1), x == 7 ? 0.0f : 64.5f);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(at(up, x, 0, c), at(down, x, 1, c));
  }

  const auto errorOf = [&](const std::string& name, const std::string& bytes) -> std::string {
    try {
      readImage(write(name, bytes));
    } catch (const InputError& error) {
      return error.what();
    }
    return "(no error)";
  };
  const std::string prefix = (dir / "x.hdr").string() + ": cannot read image: ";
  EXPECT_EQ(errorOf("x.hdr", header("-Y 2 +X 8") + rle),
            prefix + "the Radiance HDR pixels are truncated");
  EXPECT_EQ(errorOf("x.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n"),
            prefix + "the Radiance HDR header is truncated or malformed");
  EXPECT_EQ(errorOf("x.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 8\n" + rle + flat),
            prefix + "only RGBE Radiance HDR files are read, not 32-bit_rle_xyze");
  EXPECT_EQ(errorOf("x.hdr", header("+X 8 -Y 2") + rle + flat),
            prefix + "the Radiance HDR resolution line is not \"-Y height +X width\"");
  std::string overflow = rle;
  overflow[4] = '\x89';  // a run of 9 in a row of 8
  EXPECT_EQ(errorOf("x.hdr", header("-Y 2 +X 8") + overflow + flat),
            prefix + "a Radiance HDR scanline's runs overflow the row");
  // A header claiming 8192 x 8192 (768 MB of floats) over a few bytes is refused before
  // anything is allocated, as is one beyond what any image may hold.
  EXPECT_EQ(errorOf("x.hdr", header("-Y 8192 +X 8192") + rle),
            prefix + "the Radiance HDR pixels are truncated");
  EXPECT_TRUE(errorOf("x.hdr", header("-Y 16384 +X 16384") + rle)
                  .starts_with(prefix + "16384x16384 with 3 channels is too large"));
}

// The whole point: `omnishadow diff` of PNG and EXR files maps no OpenImageIO library; a TIFF
// does. LD_DEBUG=files makes the dynamic loader name every library it opens.
TEST(ImageReaderTest, OnlyOtherFormatsLoadOpenImageIO) {
  TempDir dir;
  const std::vector<std::uint8_t> pixels(4 * 4 * 3, 100);
  writePng(dir / "a.png", 4, 4, 3, pixels);
  writeExr(dir / "a.exr", FloatImage{4, 4, {"R", "G", "B"}, FloatPixels(48, 0.5f)},
           ExrPixelType::Half);
  auto output = OIIO::ImageOutput::create("tiff");
  ASSERT_TRUE(output);
  ASSERT_TRUE(
      output->open((dir / "a.tif").string(), OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(output->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  ASSERT_TRUE(output->close());

  test_support::RunOptions options;
  options.environment = {"LD_DEBUG=files"};
  const auto direct = test_support::runOmnishadow(
      {"diff", (dir / "a.png").string(), (dir / "a.exr").string(), "--channels", "R"}, options);
  EXPECT_NE(direct.status, 2) << direct.err;
  EXPECT_NE(direct.err.find("libOpenEXR"), std::string::npos) << "LD_DEBUG gave no list";
  EXPECT_EQ(direct.err.find("libOpenImageIO"), std::string::npos);
  // Nor of Radiance HDR files (panoramas for environment lighting).
  std::ofstream(dir / "a.hdr", std::ios::binary)
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n"
      << std::string("\x80\x80\x80\x81\x80\x80\x80\x81", 8);
  const auto hdr = test_support::runOmnishadow(
      {"diff", (dir / "a.hdr").string(), (dir / "a.hdr").string()}, options);
  EXPECT_EQ(hdr.status, 0) << hdr.err;
  EXPECT_EQ(hdr.err.find("libOpenImageIO"), std::string::npos);
  const auto tiff = test_support::runOmnishadow(
      {"diff", (dir / "a.tif").string(), (dir / "a.tif").string()}, options);
  EXPECT_EQ(tiff.status, 0) << tiff.out;
  EXPECT_NE(tiff.err.find("libOpenImageIO"), std::string::npos);
}

TEST(PngEncoderTest, EveryFilterAndLevelDecodesToThePixels) {
  TempDir dir;
  const int width = 37, height = 11;
  for (int channels = 1; channels <= 4; ++channels) {
    std::vector<std::uint8_t> pixels(std::size_t(width) * height * channels);
    for (std::size_t i = 0; i < pixels.size(); ++i)
      pixels[i] = static_cast<std::uint8_t>((i * i * 7 + i / 5) % 251);
    for (int filter : {kAdaptivePngFilter, 0, 1, 2, 3, 4})
      for (int level : {1, 2, 6, 12}) {
        SCOPED_TRACE(std::to_string(channels) + " channels, filter " + std::to_string(filter) +
                     ", level " + std::to_string(level));
        std::ofstream(dir / "a.png", std::ios::binary)
            << encodePng(width, height, channels, pixels, {level, filter});
        const FloatImage decoded = readWithOiio(dir / "a.png");  // an independent decoder
        ASSERT_EQ(decoded.pixels.size(), pixels.size());
        for (std::size_t i = 0; i < pixels.size(); ++i)
          ASSERT_EQ(std::lround(decoded.pixels[i] * 255.0f), pixels[i]) << "at " << i;
      }
  }
}

// IHDR, IDAT, IEND and nothing else: no gamma, time, text or offset chunks.
TEST(PngEncoderTest, WritesOnlyHeaderDataAndEnd) {
  const std::vector<std::uint8_t> pixels(5 * 3 * 4, 9);
  const std::string png = encodePng(5, 3, 4, pixels);
  std::vector<std::string> chunks;
  for (std::size_t at = 8; at + 8 <= png.size();) {
    const auto length = (std::uint32_t(std::uint8_t(png[at])) << 24) |
                        (std::uint32_t(std::uint8_t(png[at + 1])) << 16) |
                        (std::uint32_t(std::uint8_t(png[at + 2])) << 8) | std::uint8_t(png[at + 3]);
    chunks.push_back(png.substr(at + 4, 4));
    at += 12 + length;
  }
  EXPECT_EQ(chunks, (std::vector<std::string>{"IHDR", "IDAT", "IEND"}));
}

}  // namespace
}  // namespace omnishadow::image_reader_test
