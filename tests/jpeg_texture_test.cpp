// JPEG textures, decoded by libjpeg-turbo (renderer/scene/jpeg_decoder.cpp): texels where the
// source put them, grey and damaged files, what libjpeg-turbo cannot turn into RGB left to
// stb_image, and how far the two decoders' pictures lie apart. The JPEGs are made here with
// TurboJPEG's encoder from known pixels.
#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <turbojpeg.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "renderer/scene/gltf_loader.h"
#include "tests/support/extension_textures.h"
#include "tests/support/input_error.h"
#include "tests/support/temp_folder.h"
#include "tests/support/textured_triangle.h"

namespace omnishadow::jpeg_texture_test {
namespace {

using test_support::TempFolder;
namespace fs = std::filesystem;

// `pixels` (first row = top) in `format` (TJPF_RGB, TJPF_GRAY, TJPF_CMYK) as a JPEG.
std::vector<unsigned char> encodeJpeg(int width, int height,
                                      const std::vector<std::uint8_t>& pixels, int format,
                                      int subsampling, int quality) {
  tjhandle handle = tjInitCompress();
  unsigned char* jpeg = nullptr;
  unsigned long size = 0;
  const int status = tjCompress2(handle, pixels.data(), width, 0, height, format, &jpeg, &size,
                                 subsampling, quality, 0);
  std::vector<unsigned char> bytes;
  if (status == 0) bytes.assign(jpeg, jpeg + size);
  tjFree(jpeg);
  tjDestroy(handle);
  EXPECT_EQ(status, 0) << tjGetErrorStr2(nullptr);
  return bytes;
}

// The shared corners picture (tests/support/extension_textures.h) without its alpha.
std::vector<std::uint8_t> cornersPicture(int width, int height) {
  const std::vector<std::uint8_t> rgba = test_support::cornersPictureRgba(width, height);
  std::vector<std::uint8_t> rgb;
  for (std::size_t i = 0; i < rgba.size(); i += 4) rgb.insert(rgb.end(), &rgba[i], &rgba[i + 3]);
  return rgb;
}

using Storage = test_support::ImageStorage;

// A scene of one textured triangle whose image is `jpeg`, in a .glb's bufferView or in a file
// next to a .gltf.
Scene loadWithJpeg(const TempFolder& folder, const std::vector<unsigned char>& jpeg,
                   Storage storage) {
  return loadGltf(test_support::writeTexturedTriangle(
      folder.path(), {{jpeg, "photo", "image/jpeg", "photo.jpg", ""}}, storage));
}

int largestDifference(const PixelBytes& a, const std::vector<std::uint8_t>& b) {
  EXPECT_EQ(a.size(), b.size());
  int largest = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    largest = std::max(largest, std::abs(int(a[i]) - int(b[i])));
  return largest;
}

std::vector<std::uint8_t> rgbToRgba(const std::vector<std::uint8_t>& rgb) {
  std::vector<std::uint8_t> rgba;
  for (std::size_t i = 0; i < rgb.size(); i += 3)
    rgba.insert(rgba.end(), {rgb[i], rgb[i + 1], rgb[i + 2], 255});
  return rgba;
}

TEST(JpegTexture, DecodesToTheSourceTexelsTopRowFirstFromABufferViewOrAFile) {
  TempFolder folder("jpeg");
  constexpr int kWidth = 64, kHeight = 48;
  const std::vector<std::uint8_t> rgb = cornersPicture(kWidth, kHeight);
  const std::vector<unsigned char> jpeg =
      encodeJpeg(kWidth, kHeight, rgb, TJPF_RGB, TJSAMP_444, 100);
  const Scene fromView = loadWithJpeg(folder, jpeg, Storage::BufferView);
  const Scene fromFile = loadWithJpeg(folder, jpeg, Storage::File);
  ASSERT_EQ(fromView.images.size(), 1u);
  ASSERT_EQ(fromFile.images.size(), 1u);
  const Image& image = fromView.images[0];
  EXPECT_EQ(image.width, kWidth);
  EXPECT_EQ(image.height, kHeight);
  // Quality 100 without chroma subsampling: within a couple of steps of the source, alpha opaque.
  EXPECT_LE(largestDifference(image.rgba, rgbToRgba(rgb)), 3);
  EXPECT_EQ(fromFile.images[0].rgba, image.rgba);
  EXPECT_TRUE(fromView.warnings.empty());
}

TEST(JpegTexture, GreyJpegGivesEqualRgbAndOpaqueAlpha) {
  TempFolder folder("jpeg");
  std::vector<std::uint8_t> grey;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) grey.push_back(static_cast<std::uint8_t>(10 * x + y));
  const Scene scene = loadWithJpeg(folder, encodeJpeg(24, 16, grey, TJPF_GRAY, TJSAMP_GRAY, 100),
                                   Storage::BufferView);
  const Image& image = scene.images.at(0);
  ASSERT_EQ(image.rgba.size(), grey.size() * 4);
  int largest = 0;
  for (std::size_t i = 0; i < grey.size(); ++i) {
    EXPECT_EQ(image.rgba[4 * i], image.rgba[4 * i + 1]);
    EXPECT_EQ(image.rgba[4 * i], image.rgba[4 * i + 2]);
    EXPECT_EQ(image.rgba[4 * i + 3], 255);
    largest = std::max(largest, std::abs(int(image.rgba[4 * i]) - int(grey[i])));
  }
  EXPECT_LE(largest, 2);
}

// A cut file: libjpeg fills in the missing blocks and says so, as a warning naming the image;
// the rows before the cut are the picture's.
TEST(JpegTexture, TruncatedJpegLoadsWithAWarningNamingTheImage) {
  constexpr int kWidth = 64, kHeight = 64;
  const std::vector<std::uint8_t> rgb = cornersPicture(kWidth, kHeight);
  std::vector<unsigned char> jpeg = encodeJpeg(kWidth, kHeight, rgb, TJPF_RGB, TJSAMP_444, 100);
  const std::vector<unsigned char> whole = jpeg;
  jpeg.resize(jpeg.size() / 2);
  for (Storage storage : {Storage::BufferView, Storage::File}) {
    TempFolder folder("jpeg");
    const Scene scene = loadWithJpeg(folder, jpeg, storage);
    const Image& image = scene.images.at(0);
    EXPECT_EQ(image.width, kWidth);
    EXPECT_EQ(image.height, kHeight);
    ASSERT_EQ(scene.warnings.size(), 1u);
    const std::string& warning = scene.warnings[0];
    EXPECT_NE(warning.find("images[0] \"photo\": "), std::string::npos) << warning;
    EXPECT_NE(warning.find("damaged JPEG data"), std::string::npos) << warning;
    const std::vector<std::uint8_t> firstRows(image.rgba.begin(),
                                              image.rgba.begin() + 8 * kWidth * 4);
    const std::vector<std::uint8_t> source = rgbToRgba(rgb);
    EXPECT_LE(largestDifference(firstRows, {source.begin(), source.begin() + 8 * kWidth * 4}), 3);
  }
  TempFolder folder("jpeg");
  EXPECT_TRUE(loadWithJpeg(folder, whole, Storage::BufferView).warnings.empty());
}

// libjpeg-turbo does not convert CMYK to RGB; stb_image, which decoded every JPEG before,
// still gets those.
TEST(JpegTexture, CmykJpegIsLeftToStbImage) {
  TempFolder folder("jpeg");
  std::vector<std::uint8_t> cmyk;
  for (int i = 0; i < 16 * 16; ++i) cmyk.insert(cmyk.end(), {0, 255, 255, 0});  // 100% M + Y
  const std::vector<unsigned char> jpeg = encodeJpeg(16, 16, cmyk, TJPF_CMYK, TJSAMP_444, 100);
  tinygltf::Image reference;
  std::string error, warning;
  const bool stbDecodes = tinygltf::LoadImageData(
      &reference, 0, &error, &warning, 0, 0, jpeg.data(), static_cast<int>(jpeg.size()), nullptr);
  ASSERT_TRUE(stbDecodes) << error;
  const Scene scene = loadWithJpeg(folder, jpeg, Storage::BufferView);
  EXPECT_EQ(scene.images.at(0).rgba, reference.image);
}

// What the switch from stb_image changed: a photo-like 4:2:0 JPEG decodes to within 3 steps of
// stb_image's picture (2 here), and most texels to the same bytes (95% here), but not all.
TEST(JpegTexture, DiffersFromStbImageByAtMostThreeSteps) {
  TempFolder folder("jpeg");
  constexpr int kWidth = 256, kHeight = 192;
  std::vector<std::uint8_t> rgb = cornersPicture(kWidth, kHeight);
  std::uint32_t state = 12345;
  for (std::uint8_t& value : rgb) {  // texture: a little noise on the gradient
    state = state * 1664525u + 1013904223u;
    value = static_cast<std::uint8_t>(std::clamp(int(value) + int(state >> 29) - 4, 0, 255));
  }
  const std::vector<unsigned char> jpeg =
      encodeJpeg(kWidth, kHeight, rgb, TJPF_RGB, TJSAMP_420, 90);
  tinygltf::Image reference;
  std::string error, warning;
  ASSERT_TRUE(tinygltf::LoadImageData(&reference, 0, &error, &warning, 0, 0, jpeg.data(),
                                      static_cast<int>(jpeg.size()), nullptr))
      << error;
  const Scene scene = loadWithJpeg(folder, jpeg, Storage::BufferView);
  const Image& image = scene.images.at(0);
  EXPECT_LE(largestDifference(image.rgba, reference.image), 3);
  std::size_t same = 0;
  for (std::size_t i = 0; i < image.rgba.size(); ++i) same += image.rgba[i] == reference.image[i];
  EXPECT_GT(double(same) / double(image.rgba.size()), 0.9);
  EXPECT_LT(same, image.rgba.size()) << "the same bytes as stb_image: is libjpeg-turbo used?";
}

// A scene of one triangle and one image per entry of `images`: in a .glb, each in its own
// bufferView, or in a .gltf, each in a file of its own.
fs::path sceneWithImages(const TempFolder& folder,
                         const std::vector<std::vector<unsigned char>>& images,
                         Storage storage = Storage::BufferView) {
  std::vector<test_support::SceneImage> files;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string name = "photo" + std::to_string(i);
    files.push_back({images[i], name, "image/jpeg", name + ".jpg", ""});
  }
  return test_support::writeTexturedTriangle(folder.path(), files, storage, "images");
}

// A file's images are decoded several at a time, from bufferViews and from files of their own:
// each image still gets its own texels, and of several broken images the error names the
// first, as when they were decoded one by one.
TEST(JpegTexture, ImagesDecodedTogetherKeepTheirOwnTexelsAndTheFirstErrorWins) {
  TempFolder folder("jpeg");
  std::vector<std::vector<unsigned char>> jpegs;
  std::vector<std::vector<std::uint8_t>> sources;
  for (int i = 0; i < 7; ++i) {
    std::vector<std::uint8_t> rgb = cornersPicture(32 + 8 * i, 24);
    for (std::size_t k = 0; k < rgb.size(); k += 3) rgb[k] = static_cast<std::uint8_t>(30 * i);
    jpegs.push_back(encodeJpeg(32 + 8 * i, 24, rgb, TJPF_RGB, TJSAMP_444, 100));
    sources.push_back(rgbToRgba(rgb));
  }
  for (Storage storage : {Storage::BufferView, Storage::File}) {
    const Scene scene = loadGltf(sceneWithImages(folder, jpegs, storage));
    ASSERT_EQ(scene.images.size(), jpegs.size());
    for (std::size_t i = 0; i < jpegs.size(); ++i) {
      SCOPED_TRACE(i);
      EXPECT_EQ(scene.images[i].width, 32 + 8 * static_cast<int>(i));
      // Within a few codes of its own source (4 here at most); another image's red differs by 30.
      EXPECT_LE(largestDifference(scene.images[i].rgba, sources[i]), 8);
    }
  }

  std::vector<std::vector<unsigned char>> broken = jpegs;
  broken[5] = std::vector<unsigned char>(64, 0x5a);  // not an image at all
  broken[2][4] = 0xc3;                               // SOF3 where the frame header starts
  broken[2].resize(40);
  const fs::path path = sceneWithImages(folder, broken);
  const std::string message = test_support::inputError([&] { loadGltf(path); });
  EXPECT_EQ(message.rfind(path.string() + ": images[2] \"photo2\": ", 0), 0u) << message;
}

// `jpeg` with its last scan (SOS to EOI) repeated `copies` more times.
std::vector<unsigned char> withRepeatedLastScan(const std::vector<unsigned char>& jpeg,
                                                int copies) {
  std::size_t sos = 0;
  for (std::size_t i = 0; i + 1 < jpeg.size(); ++i)
    if (jpeg[i] == 0xFF && jpeg[i + 1] == 0xDA) sos = i;
  const std::size_t eoi = jpeg.size() - 2;
  std::vector<unsigned char> out(jpeg.begin(), jpeg.begin() + static_cast<std::ptrdiff_t>(eoi));
  for (int c = 0; c < copies; ++c)
    out.insert(out.end(), jpeg.begin() + static_cast<std::ptrdiff_t>(sos),
               jpeg.begin() + static_cast<std::ptrdiff_t>(eoi));
  out.insert(out.end(), {0xFF, 0xD9});
  return out;
}

// A JPEG that libjpeg-turbo refuses is an error naming the image, not tried again with
// stb_image: here a progressive file of more scans than TurboJPEG's limit, a way to make a
// decoder work for minutes with a small file.
TEST(JpegTexture, AJpegLibjpegTurboRefusesIsAnErrorNamingTheImage) {
  TempFolder folder("jpeg");
  const std::vector<std::uint8_t> rgb = cornersPicture(64, 48);
  tjhandle handle = tjInitCompress();
  unsigned char* encoded = nullptr;
  unsigned long size = 0;
  ASSERT_EQ(tjCompress2(handle, rgb.data(), 64, 0, 48, TJPF_RGB, &encoded, &size, TJSAMP_420, 90,
                        TJFLAG_PROGRESSIVE),
            0);
  const std::vector<unsigned char> progressive(encoded, encoded + size);
  tjFree(encoded);
  tjDestroy(handle);
  EXPECT_TRUE(loadWithJpeg(folder, progressive, Storage::BufferView).warnings.empty());
  const std::vector<unsigned char> scans = withRepeatedLastScan(progressive, 600);
  const fs::path path = sceneWithImages(folder, {scans});
  const std::string message = test_support::inputError([&] { loadGltf(path); });
  EXPECT_EQ(message.rfind(path.string() + ": images[0] \"photo0\": cannot decode the JPEG: ", 0),
            0u)
      << message;
}

}  // namespace
}  // namespace omnishadow::jpeg_texture_test
