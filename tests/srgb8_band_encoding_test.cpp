// The 8-bit beauty encoded on the CPU while the float target is read back in bands
// (renderer/passes/srgb8_band_encoding.h): toSrgb8()'s bytes for every pixel, whatever the size
// (one band, a last band cut short, more bands than buffers, one thread or two) and the row
// order asked for; outside the region the frame drew in, the background's bytes.
#include "renderer/passes/srgb8_band_encoding.h"

#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/output/display_transform.h"
#include "renderer/output/image_writer.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::srgb8_band_encoding_test {
namespace {

// A float RGBA picture whose every row and column differs, with values below 0, above 1 and
// on both sides of sRGB steps, first row = GL's first (the bottom).
std::vector<float> picture(int width, int height) {
  std::vector<float> rgba(static_cast<std::size_t>(width) * height * 4);
  std::uint32_t state = 12345u;
  for (std::size_t i = 0; i < rgba.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    rgba[i] = -0.05f + 1.2f * static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
  }
  return rgba;
}

// The same picture top row first unless `glRowOrder`, as a FloatImage for toSrgb8().
FloatImage asFrame(const std::vector<float>& glRows, int width, int height, bool glRowOrder) {
  FloatImage image{width, height, {"R", "G", "B", "A"}, {}};
  image.pixels.resize(glRows.size());
  const std::size_t row = static_cast<std::size_t>(width) * 4;
  for (int y = 0; y < height; ++y) {
    const std::size_t from = static_cast<std::size_t>(glRowOrder ? y : height - 1 - y) * row;
    for (std::size_t i = 0; i < row; ++i) image.pixels[y * row + i] = glRows[from + i];
  }
  return image;
}

TEST(Srgb8BandEncoding, EveryByteIsToSrgb8OfTheFloatTarget) {
  test_support::sharedRenderer();  // its GL context is current here
  struct Size {
    int width, height;
  };
  // With bands of 8 rows through 4 buffers: 1x1, one band; 61x37, one thread, 5 bands, the last
  // of 5 rows; 160x96, 12 whole bands; 704x403, two threads, 51 bands, the last of 3 rows.
  for (const Size size : {Size{1, 1}, Size{61, 37}, Size{160, 96}, Size{704, 403}}) {
    const std::vector<float> rows = picture(size.width, size.height);
    gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.get(), 1, GL_RGBA32F, size.width, size.height);
    glTextureSubImage2D(texture.get(), 0, 0, 0, size.width, size.height, GL_RGBA, GL_FLOAT,
                        rows.data());
    for (const bool glRowOrder : {false, true})
      for (const float exposure : {0.0f, -1.25f}) {
        SCOPED_TRACE(::testing::Message() << size.width << "x" << size.height << ", glRowOrder "
                                          << glRowOrder << ", exposure " << exposure);
        const Srgb8Image encoded =
            readSrgb8InBands(texture.get(), size.width, size.height,
                             TexelRegion(TexelRect::whole(size.width, size.height)),
                             std::exp2(exposure), glRowOrder);
        EXPECT_EQ(encoded.width, size.width);
        EXPECT_EQ(encoded.height, size.height);
        const std::vector<std::uint8_t> expected =
            toSrgb8(asFrame(rows, size.width, size.height, glRowOrder), exposure);
        ASSERT_EQ(encoded.rgb.size(), expected.size());
        std::size_t differ = 0;
        for (std::size_t i = 0; i < expected.size(); ++i) differ += encoded.rgb[i] != expected[i];
        EXPECT_EQ(differ, 0u);
      }
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  }
}

TEST(Srgb8BandEncoding, OutsideTheDrawnRegionEveryPixelIsTheBackground) {
  test_support::sharedRenderer();
  const int width = 704, height = 460;
  const std::vector<float> rows = picture(width, height);
  // What a frame holds: the picture inside the region, the clear value (zeros) elsewhere. The
  // texture holds the picture everywhere, so a pixel read back from outside the region shows.
  gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.get(), 1, GL_RGBA32F, width, height);
  glTextureSubImage2D(texture.get(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, rows.data());
  // GL's coordinates (y up): a corner rectangle, one inside starting at an odd row whose last
  // band is short, one of two threads (at least 2^18 pixels), one pixel, a row, none; and
  // regions of several rectangles: side by side in one band and apart in others, one starting
  // and one ending inside a band, a column beside a frame-wide row, and two of two threads.
  const std::vector<TexelRegion> regions = {
      TexelRegion(TexelRect{0, 0, 37, 9}),
      TexelRegion(TexelRect{5, 3, 66, 44}),
      TexelRegion(TexelRect{61, 17, 704, 459}),
      TexelRegion(TexelRect{703, 459, 704, 460}),
      TexelRegion(TexelRect{0, 200, 704, 201}),
      TexelRegion(),
      TexelRegion::unionOf({{3, 5, 40, 30}, {100, 12, 130, 21}, {20, 25, 120, 70}},
                           TexelRect::whole(width, height)),
      TexelRegion::unionOf({{0, 0, 1, 460}, {0, 230, 704, 233}, {690, 3, 701, 11}},
                           TexelRect::whole(width, height)),
      TexelRegion::unionOf({{0, 0, 400, 420}, {401, 40, 704, 460}},
                           TexelRect::whole(width, height))};
  for (const TexelRegion& region : regions)
    for (const bool glRowOrder : {false, true})
      for (const float exposure : {0.0f, 1.5f}) {
        const TexelRect bounds = region.bounds();
        SCOPED_TRACE(::testing::Message()
                     << region.rects().size() << " rects within " << bounds.x0 << "," << bounds.y0
                     << " to " << bounds.x1 << "," << bounds.y1 << ", glRowOrder " << glRowOrder
                     << ", exposure " << exposure);
        std::vector<float> frame(rows.size(), 0.0f);
        for (const TexelRect& rect : region.rects())
          for (int y = rect.y0; y < rect.y1; ++y)
            for (int x = rect.x0; x < rect.x1; ++x)
              for (int c = 0; c < 4; ++c) {
                const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 4 + c;
                frame[i] = rows[i];
              }
        const Srgb8Image encoded =
            readSrgb8InBands(texture.get(), width, height, region, std::exp2(exposure), glRowOrder);
        const std::vector<std::uint8_t> expected =
            toSrgb8(asFrame(frame, width, height, glRowOrder), exposure);
        ASSERT_EQ(encoded.rgb.size(), expected.size());
        std::size_t differ = 0;
        for (std::size_t i = 0; i < expected.size(); ++i) differ += encoded.rgb[i] != expected[i];
        EXPECT_EQ(differ, 0u);
      }
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace
}  // namespace omnishadow::srgb8_band_encoding_test
