// An RGBA8UI target read back (readSrgb8Texture) through a kept pixel pack buffer or into memory
// of its own: each pixel's RGB in the row order asked for, whether the buffer is new, grown for
// a larger target, or reused by a smaller one after it; into memory, only the rectangle the
// frame drew in, with zeros (the clear value) around it.
#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/pixel_pack_buffer.h"
#include "renderer/passes/srgb8_resolve.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::srgb8_readback_test {
namespace {

// RGBA bytes whose every pixel differs, GL's first row (the bottom) first.
std::vector<std::uint8_t> texels(int width, int height, std::uint32_t seed) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
  for (std::size_t i = 0; i < rgba.size(); ++i) {
    seed = seed * 1664525u + 1013904223u;
    rgba[i] = static_cast<std::uint8_t>(seed >> 24);
  }
  return rgba;
}

TEST(Srgb8Readback, EachPixelsRgbInTheRowOrderAskedForThroughOneKeptBuffer) {
  test_support::sharedRenderer();  // its GL context is current here
  gl::PixelPackBuffer readback;
  struct Size {
    int width, height;
  };
  // New, grown twice, then reused by smaller targets (the mapping covers only their bytes); odd
  // widths, whose last one or two pixels readSrgb8Texture copies byte by byte.
  for (const Size size : {Size{3, 2}, Size{61, 37}, Size{704, 403}, Size{1, 1}, Size{64, 5}}) {
    const std::vector<std::uint8_t> rgba =
        texels(size.width, size.height, static_cast<std::uint32_t>(size.width * 7919));
    gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(texture.get(), 1, GL_RGBA8UI, size.width, size.height);
    glTextureSubImage2D(texture.get(), 0, 0, 0, size.width, size.height, GL_RGBA_INTEGER,
                        GL_UNSIGNED_BYTE, rgba.data());
    for (const bool glRowOrder : {false, true})
      for (gl::PixelPackBuffer* through : {&readback, static_cast<gl::PixelPackBuffer*>(nullptr)}) {
        const Srgb8Image image = readSrgb8Texture(
            texture.get(), size.width, size.height,
            TexelRegion(TexelRect::whole(size.width, size.height)), glRowOrder, through);
        ASSERT_EQ(image.width, size.width);
        ASSERT_EQ(image.height, size.height);
        ASSERT_EQ(image.rgb.size(), static_cast<std::size_t>(size.width) * size.height * 3);
        std::size_t wrong = 0;
        for (int y = 0; y < size.height; ++y) {
          const int glRow = glRowOrder ? y : size.height - 1 - y;
          for (int x = 0; x < size.width; ++x)
            for (int c = 0; c < 3; ++c)
              wrong += image.rgb[(static_cast<std::size_t>(y) * size.width + x) * 3 + c] !=
                       rgba[(static_cast<std::size_t>(glRow) * size.width + x) * 4 + c];
        }
        EXPECT_EQ(wrong, 0u) << size.width << "x" << size.height << (glRowOrder ? " GL order" : "")
                             << (through ? " through the buffer" : " into its own memory");
      }
  }
}

TEST(Srgb8Readback, IntoMemoryOnlyTheDrawnRegionIsReadAndTheRestIsZeros) {
  test_support::sharedRenderer();
  const int width = 61, height = 37;
  const std::vector<std::uint8_t> rgba = texels(width, height, 104729u);
  gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.get(), 1, GL_RGBA8UI, width, height);
  glTextureSubImage2D(texture.get(), 0, 0, 0, width, height, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE,
                      rgba.data());
  // GL's coordinates (y up). The texture holds texels outside the region too, where a frame
  // holds zeros: a pixel read from there shows. Odd widths (the row's last pixels go byte by
  // byte), a corner, one pixel, one column, the whole target and none; and regions of several
  // rectangles of different sizes, one of them wider than the first.
  const TexelRect whole = TexelRect::whole(width, height);
  const std::vector<TexelRegion> regions = {
      TexelRegion(TexelRect{3, 2, 40, 31}),
      TexelRegion(TexelRect{0, 0, 2, 1}),
      TexelRegion(TexelRect{60, 36, 61, 37}),
      TexelRegion(TexelRect{7, 0, 8, 37}),
      TexelRegion(whole),
      TexelRegion(),
      TexelRegion::unionOf({{1, 1, 5, 4}, {10, 3, 60, 30}, {2, 20, 12, 36}}, whole),
      TexelRegion::unionOf({{0, 0, 61, 2}, {30, 2, 31, 37}}, whole)};
  for (const TexelRegion& region : regions)
    for (const bool glRowOrder : {false, true}) {
      const Srgb8Image image =
          readSrgb8Texture(texture.get(), width, height, region, glRowOrder, nullptr);
      ASSERT_EQ(image.rgb.size(), static_cast<std::size_t>(width) * height * 3);
      std::size_t wrong = 0;
      for (int y = 0; y < height; ++y) {
        const int glRow = glRowOrder ? y : height - 1 - y;
        for (int x = 0; x < width; ++x) {
          const bool inside =
              std::any_of(region.rects().begin(), region.rects().end(), [&](const TexelRect& rect) {
                return glRow >= rect.y0 && glRow < rect.y1 && x >= rect.x0 && x < rect.x1;
              });
          for (int c = 0; c < 3; ++c) {
            const std::uint8_t expected =
                inside ? rgba[(static_cast<std::size_t>(glRow) * width + x) * 4 + c] : 0;
            wrong += image.rgb[(static_cast<std::size_t>(y) * width + x) * 3 + c] != expected;
          }
        }
      }
      const TexelRect bounds = region.bounds();
      EXPECT_EQ(wrong, 0u) << region.rects().size() << " rects within " << bounds.x0 << ","
                           << bounds.y0 << " to " << bounds.x1 << "," << bounds.y1
                           << (glRowOrder ? " GL order" : "");
    }
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace
}  // namespace omnishadow::srgb8_readback_test
