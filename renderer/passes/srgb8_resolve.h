#pragma once

#include <GL/glcorearb.h>

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/pixel_pack_buffer.h"
#include "renderer/gl/shader_program.h"
#include "renderer/render/frame.h"
#include "renderer/view/texel_region.h"

namespace omnishadow {

// The RGB bytes of an RGBA8UI texture of width x height, first row = top unless `glRowOrder`,
// read back through `readback`, or into memory of its own where it is null: on llvmpipe that
// took 0.9-1.1 ms a 1280x720 frame against 1.1-1.5 through a buffer (docs/performance.md).
// Into memory, only the pixels of `drawn` (GL's window coordinates: FrameTargets::drawn()) are
// read, a rectangle of it at a time, and every other one is zeros, the clear value (Box's
// steady readback 0.8 -> 0.4 ms); through the buffer the whole texture is.
Srgb8Image readSrgb8Texture(GLuint texture, int width, int height, const TexelRegion& drawn,
                            bool glRowOrder, gl::PixelPackBuffer* readback);

// The 8-bit beauty of a frame the lighting pass drew into its float target (blended or
// see-through surfaces, which an integer target cannot take): a full-screen pass encodes each
// pixel as toSrgb8() does on the CPU (shaders/srgb8_resolve.frag) into an RGBA8UI target of
// its own, which is read back: a quarter of the float target's bytes, and no pass over the
// frame on the CPU. On the H200 reading back the 1280x720 float beauty took 6.2 ms a frame
// against 2.0 for the 8-bit one (docs/performance.md).
class Srgb8Resolve {
 public:
  Srgb8Resolve();

  // `beauty`: the float target (RGBA, premultiplied); its RGB times `exposureScale`, encoded.
  // Leaves the GL's framebuffer, program, vertex array and unit 0 changed.
  Srgb8Image resolve(GLuint beauty, int width, int height, float exposureScale, bool glRowOrder);

 private:
  void resize(int width, int height);

  ShaderProgram encode_;
  gl::VertexArray empty_;
  gl::Texture target_;
  gl::Framebuffer framebuffer_;
  gl::PixelPackBuffer readback_;
  int width_ = 0, height_ = 0;
};

}  // namespace omnishadow
