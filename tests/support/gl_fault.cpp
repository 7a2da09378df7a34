// An LD_PRELOAD library that makes the omnishadow binary meet a GL error or a lost context, so
// that tests can check what one does to a render and to a batch without a hook in the product.
//
// It is armed by the upload of a texture of exactly kMarkerWidth x kMarkerHeight texels (a test
// puts one in the scene that should fail). Once armed, depending on OMNISHADOW_GL_FAULT:
//   error  the next glGetError() returns GL_INVALID_OPERATION;
//   reset  the next glGetGraphicsResetStatus() returns GL_GUILTY_CONTEXT_RESET.
//   crash  the upload itself raises SIGSEGV, as a driver bug would;
//   hang   the upload never returns (the batch's --job-timeout tests).
// And, without any marker:
//   crash-context  eglCreateContext raises SIGSEGV, as a driver that cannot start would;
//   no-shared-context  eglCreateContext fails for a context that shares another's objects (the
//                  renderer's second context, passes/shadow_worker.h);
//   error-in-shared-context  the first glGetError() in such a context returns
//                  GL_INVALID_OPERATION.
// error and reset happen once; afterwards the real GL answers again, as it would for a fresh
// context.
// OMNISHADOW_GL_MAX_CUBE_MAP_TEXTURE_SIZE=N and OMNISHADOW_GL_MAX_ARRAY_TEXTURE_LAYERS=N make
// glGetIntegerv report N as that limit, for tests of what a GL with smaller limits refuses.
//
// The GL headers are left out on purpose: their prototypes would clash with these definitions.

#include "tests/support/gl_fault.h"

#include <dlfcn.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace {

using GLenum = unsigned int;
using GLint = int;
using GLuint = unsigned int;
using GLsizei = int;

constexpr GLenum kInvalidOperation = 0x0502;
constexpr GLenum kGuiltyContextReset = 0x8253;
constexpr GLenum kMaxCubeMapTextureSize = 0x851C;
constexpr GLenum kMaxArrayTextureLayers = 0x88FF;

std::atomic<bool> armed{false};
std::atomic<void*> sharedContext{nullptr};  // the last context made sharing another's objects
std::atomic<bool> sharedErrorLeft{true};

bool faultIs(const char* kind) {
  const char* value = std::getenv("OMNISHADOW_GL_FAULT");
  return value != nullptr && std::strcmp(value, kind) == 0;
}

void armOn(GLsizei width, GLsizei height) {
  if (width == omnishadow::test_support::kGlFaultMarkerWidth &&
      height == omnishadow::test_support::kGlFaultMarkerHeight) {
    armed = true;
    if (faultIs("crash")) std::raise(SIGSEGV);
    if (faultIs("hang"))
      for (;;) ::pause();
  }
}

template <typename F>
F real(const char* name) {
  return reinterpret_cast<F>(::dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) void glTextureSubImage2D(GLuint texture, GLint level,
                                                                GLint x, GLint y, GLsizei width,
                                                                GLsizei height, GLenum format,
                                                                GLenum type, const void* pixels) {
  static const auto next =
      real<void (*)(GLuint, GLint, GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, const void*)>(
          "glTextureSubImage2D");
  armOn(width, height);
  next(texture, level, x, y, width, height, format, type, pixels);
}

__attribute__((visibility("default"))) void glTexSubImage2D(GLenum target, GLint level, GLint x,
                                                            GLint y, GLsizei width, GLsizei height,
                                                            GLenum format, GLenum type,
                                                            const void* pixels) {
  static const auto next =
      real<void (*)(GLenum, GLint, GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, const void*)>(
          "glTexSubImage2D");
  armOn(width, height);
  next(target, level, x, y, width, height, format, type, pixels);
}

__attribute__((visibility("default"))) void glTexImage2D(GLenum target, GLint level,
                                                         GLint internalFormat, GLsizei width,
                                                         GLsizei height, GLint border,
                                                         GLenum format, GLenum type,
                                                         const void* pixels) {
  static const auto next =
      real<void (*)(GLenum, GLint, GLint, GLsizei, GLsizei, GLint, GLenum, GLenum, const void*)>(
          "glTexImage2D");
  armOn(width, height);
  next(target, level, internalFormat, width, height, border, format, type, pixels);
}

__attribute__((visibility("default"))) void* eglCreateContext(void* display, void* config,
                                                              void* share, const int* attributes) {
  using Fn = void* (*)(void*, void*, void*, const int*);
  static const Fn next = real<Fn>("eglCreateContext");
  if (faultIs("crash-context")) std::raise(SIGSEGV);
  if (share != nullptr && faultIs("no-shared-context")) return nullptr;  // EGL_NO_CONTEXT
  void* context = next(display, config, share, attributes);
  if (share != nullptr) sharedContext = context;
  return context;
}

__attribute__((visibility("default"))) void glGetIntegerv(GLenum name, GLint* data) {
  using Fn = void (*)(GLenum, GLint*);
  static const Fn next = real<Fn>("glGetIntegerv");
  next(name, data);
  const char* limit =
      name == kMaxCubeMapTextureSize   ? std::getenv("OMNISHADOW_GL_MAX_CUBE_MAP_TEXTURE_SIZE")
      : name == kMaxArrayTextureLayers ? std::getenv("OMNISHADOW_GL_MAX_ARRAY_TEXTURE_LAYERS")
                                       : nullptr;
  if (limit != nullptr) *data = std::atoi(limit);
}

__attribute__((visibility("default"))) GLenum glGetError() {
  using Fn = GLenum (*)();
  static const Fn next = real<Fn>("glGetError");
  if (faultIs("error") && armed.exchange(false)) return kInvalidOperation;
  if (faultIs("error-in-shared-context")) {
    using Current = void* (*)();
    static const Current current = real<Current>("eglGetCurrentContext");
    if (sharedContext != nullptr && current() == sharedContext && sharedErrorLeft.exchange(false))
      return kInvalidOperation;
  }
  return next();
}

__attribute__((visibility("default"))) GLenum glGetGraphicsResetStatus() {
  using Fn = GLenum (*)();
  static const Fn next = real<Fn>("glGetGraphicsResetStatus");
  if (faultIs("reset") && armed.exchange(false)) return kGuiltyContextReset;
  return next();
}

}  // extern "C"
