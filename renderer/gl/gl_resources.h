#pragma once

#include <GL/glcorearb.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace omnishadow::gl {

// Move-only owner of one GL object name; deletes it on destruction. Created with the DSA
// glCreate* functions so the object exists (and can be labelled) before first bind.
template <void (*Delete)(GLuint)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(GLuint id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  GLuint get() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

namespace detail {
inline void deleteBuffer(GLuint id) {
  glDeleteBuffers(1, &id);
}
inline void deleteTexture(GLuint id) {
  glDeleteTextures(1, &id);
}
inline void deleteFramebuffer(GLuint id) {
  glDeleteFramebuffers(1, &id);
}
inline void deleteVertexArray(GLuint id) {
  glDeleteVertexArrays(1, &id);
}
inline void deleteSampler(GLuint id) {
  glDeleteSamplers(1, &id);
}
inline void deleteProgram(GLuint id) {
  glDeleteProgram(id);
}
inline void deleteShader(GLuint id) {
  glDeleteShader(id);
}
}  // namespace detail

using Buffer = Handle<detail::deleteBuffer>;
using Texture = Handle<detail::deleteTexture>;
using Framebuffer = Handle<detail::deleteFramebuffer>;
using VertexArray = Handle<detail::deleteVertexArray>;
using Sampler = Handle<detail::deleteSampler>;
using Program = Handle<detail::deleteProgram>;
using Shader = Handle<detail::deleteShader>;

inline Buffer createBuffer() {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  return Buffer(id);
}

// A buffer whose contents are replaced every frame (draw commands, light lists): its storage is
// reallocated, doubling, only when new contents outgrow it, and it always has at least one byte
// so that it can be bound.
class StreamBuffer {
 public:
  GLuint get() const { return buffer_.get(); }
  // Replaces the first `size` bytes of the buffer with `data`.
  void upload(const void* data, GLsizeiptr size) {
    const GLsizeiptr needed = std::max<GLsizeiptr>(size, 1);
    if (needed > capacity_) {
      capacity_ = std::max(needed, 2 * capacity_);
      buffer_ = createBuffer();
      glNamedBufferStorage(buffer_.get(), capacity_, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    if (size > 0) glNamedBufferSubData(buffer_.get(), 0, size, data);
  }
  template <typename T>
  void upload(const std::vector<T>& items) {
    upload(items.data(), static_cast<GLsizeiptr>(items.size() * sizeof(T)));
  }

 private:
  Buffer buffer_;
  GLsizeiptr capacity_ = 0;
};
inline Texture createTexture(GLenum target) {
  GLuint id = 0;
  glCreateTextures(target, 1, &id);
  return Texture(id);
}
inline Framebuffer createFramebuffer() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  return Framebuffer(id);
}
inline VertexArray createVertexArray() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  return VertexArray(id);
}
inline Sampler createSampler() {
  GLuint id = 0;
  glCreateSamplers(1, &id);
  return Sampler(id);
}

}  // namespace omnishadow::gl
