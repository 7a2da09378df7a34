#include "renderer/passes/srgb8_resolve.h"

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/scene/srgb_transfer.h"

namespace omnishadow {

namespace {

// One row of RGBA bytes as RGB, two pixels a step through 64-bit words: byte by byte, the
// copy took 0.56 ms of a 1280x720 frame's readback, this way 0.28. A step stores 8 bytes for
// its 6, into the next pixel's place, which a later step fills; so each step needs a pixel
// after its pair, and the row's last one or two go byte by byte.
void rgbaRowToRgb(const std::uint8_t* from, std::uint8_t* to, int width) {
  int x = 0;
  if constexpr (std::endian::native == std::endian::little) {
    for (; x + 3 <= width; x += 2, from += 8, to += 6) {
      std::uint64_t pair = 0;
      std::memcpy(&pair, from, 8);
      pair = (pair & 0xFFFFFFull) | ((pair >> 8) & 0xFFFFFF000000ull);
      std::memcpy(to, &pair, 8);
    }
  }
  for (; x < width; ++x, from += 4, to += 3) {
    to[0] = from[0];
    to[1] = from[1];
    to[2] = from[2];
  }
}

}  // namespace

Srgb8Image readSrgb8Texture(GLuint texture, int width, int height, const TexelRegion& drawn,
                            bool glRowOrder, gl::PixelPackBuffer* readback) {
  const int w = width, h = height;
  // Outside `drawn` every pixel holds the clear value, zeros, which the image starts with.
  Srgb8Image image{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 3)};
  const TexelRegion read = drawn.clipped(TexelRect::whole(w, h));
  if (read.empty()) return image;
  // The pixels of `rect` from `rgba`, which holds just them, GL's rows first; the copy into RGB
  // turns the rows around too.
  const auto toRgb = [&](const std::uint8_t* rgba, const TexelRect& rect) {
    const int rectWidth = rect.x1 - rect.x0;
    for (int glRow = rect.y0; glRow < rect.y1; ++glRow) {
      const int y = glRowOrder ? glRow : h - 1 - glRow;
      rgbaRowToRgb(rgba + static_cast<std::size_t>(glRow - rect.y0) * rectWidth * 4,
                   image.rgb.data() + (static_cast<std::size_t>(y) * w + rect.x0) * 3, rectWidth);
    }
  };
  if (readback) {
    // A GPU's readback: the whole target through the kept buffer.
    const TexelRect whole = TexelRect::whole(w, h);
    const std::size_t bytes = static_cast<std::size_t>(w) * h * 4;
    toRgb(readback->read(texture, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE, bytes).data(), whole);
  } else {
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(read.largestRectTexels()) * 4);
    for (const TexelRect& rect : read.rects()) {
      const std::size_t bytes = static_cast<std::size_t>(rect.texels()) * 4;
      glGetTextureSubImage(texture, 0, rect.x0, rect.y0, 0, rect.x1 - rect.x0, rect.y1 - rect.y0, 1,
                           GL_RGBA_INTEGER, GL_UNSIGNED_BYTE, static_cast<GLsizei>(bytes),
                           rgba.data());
      toRgb(rgba.data(), rect);
    }
  }
  return image;
}

Srgb8Resolve::Srgb8Resolve()
    : encode_("fullscreen.vert", "srgb8_resolve.frag", contract::shaderContractDefines()),
      empty_(gl::createVertexArray()) {
  const std::array<float, 256>& steps = srgb8Steps();
  encode_.set("uSrgb8Next", steps.data(), static_cast<int>(steps.size()));
}

void Srgb8Resolve::resize(int width, int height) {
  if (width == width_ && height == height_) return;
  framebuffer_ = gl::createFramebuffer();
  target_ = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(target_.get(), 1, GL_RGBA8UI, width, height);
  glNamedFramebufferTexture(framebuffer_.get(), GL_COLOR_ATTACHMENT0, target_.get(), 0);
  glNamedFramebufferDrawBuffer(framebuffer_.get(), GL_COLOR_ATTACHMENT0);
  if (glCheckNamedFramebufferStatus(framebuffer_.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("cannot create the " + std::to_string(width) + "x" + std::to_string(height) +
                      " 8-bit beauty target");
  width_ = width;
  height_ = height;
}

Srgb8Image Srgb8Resolve::resolve(GLuint beauty, int width, int height, float exposureScale,
                                 bool glRowOrder) {
  resize(width, height);
  gl::RasterState state;
  state.depth.test = false;  // a full-screen triangle, no depth attachment
  state.viewport = {0, 0, width, height};
  state.apply();
  glBindVertexArray(empty_.get());
  // texelFetch alone: no sampler state is read, but a sampler left bound must not compare.
  glBindSampler(0, 0);
  glBindTextureUnit(0, beauty);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  encode_.use();
  encode_.set("uExposureScale", exposureScale);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  gl::RasterState::restoreDefaults();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the 8-bit beauty's encoding");
  return readSrgb8Texture(target_.get(), width, height,
                          TexelRegion(TexelRect::whole(width, height)), glRowOrder, &readback_);
}

}  // namespace omnishadow
