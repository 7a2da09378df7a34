#include "renderer/gl/pixel_pack_buffer.h"

#include <string>

#include "renderer/core/errors.h"

namespace omnishadow::gl {

PixelPackBuffer::Mapping::Mapping(GLuint buffer, std::size_t bytes)
    : buffer_(buffer),
      data_(static_cast<const std::uint8_t*>(
          glMapNamedBufferRange(buffer, 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT))) {
  if (!data_)
    throw RenderError("cannot map the " + std::to_string(bytes) + "-byte readback buffer");
}

PixelPackBuffer::Mapping::~Mapping() {
  glUnmapNamedBuffer(buffer_);
}

PixelPackBuffer::Mapping PixelPackBuffer::read(GLuint texture, GLenum format, GLenum type,
                                               std::size_t bytes) {
  if (bytes > capacity_) {
    buffer_ = createBuffer();
    // Client storage: the driver keeps it in the host's memory, where the GPU writes it once and
    // the CPU reads it without another copy.
    glNamedBufferStorage(buffer_.get(), static_cast<GLsizeiptr>(bytes), nullptr,
                         GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT);
    capacity_ = bytes;
  }
  glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_.get());
  glGetTextureImage(texture, 0, format, type, static_cast<GLsizei>(bytes), nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  return Mapping(buffer_.get(), bytes);
}

}  // namespace omnishadow::gl
