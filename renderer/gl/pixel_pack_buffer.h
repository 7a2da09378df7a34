#pragma once

#include <GL/glcorearb.h>

#include <cstddef>
#include <cstdint>

#include "renderer/gl/gl_resources.h"

namespace omnishadow::gl {

// A buffer that a texture is read back into (GL_PIXEL_PACK_BUFFER), kept from frame to frame
// and read where the driver put it: glGetTextureImage into the caller's memory made the driver
// copy the frame a second time, into pages fresh to the process each frame.
class PixelPackBuffer {
 public:
  // The bytes a read maps; unmapped when it goes.
  class Mapping {
   public:
    Mapping(GLuint buffer, std::size_t bytes);
    ~Mapping();
    Mapping(const Mapping&) = delete;
    Mapping& operator=(const Mapping&) = delete;
    const std::uint8_t* data() const { return data_; }

   private:
    GLuint buffer_;
    const std::uint8_t* data_;
  };

  // Level 0 of `texture` as `format` and `type`, `bytes` in all; waits for the GPU's copy.
  Mapping read(GLuint texture, GLenum format, GLenum type, std::size_t bytes);

 private:
  Buffer buffer_;
  std::size_t capacity_ = 0;
};

}  // namespace omnishadow::gl
