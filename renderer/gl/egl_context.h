#pragma once

#include <memory>
#include <string>

#include "renderer/core/context_options.h"

namespace omnishadow {

// Headless OpenGL 4.5 core context, made current on the calling thread. No window, no surface,
// no X: rendering goes into the caller's framebuffer objects. A thread has one current context:
// where it holds more than one, its users call makeCurrent() before their GL calls.
// Tries the EGL device platform (hardware devices first, then Mesa's software device), then
// Mesa's surfaceless platform. Throws RenderError listing every attempt and what EGL said.
class EglContext {
 public:
  explicit EglContext(const ContextOptions& options);
  // A second context on `shareWith`'s display that shares its textures, buffers, programs and
  // samplers (not its vertex arrays or framebuffers), current on the calling thread, which may
  // be another thread than shareWith's. Must be destroyed before `shareWith`.
  EglContext(const EglContext& shareWith, bool debug);
  ~EglContext();  // with impl_, neither copyable nor movable

  // Makes this context current on the calling thread again, where another context of that
  // thread (another renderer's, made or ended after this one) took its place. Throws
  // RenderError when EGL refuses.
  void makeCurrent() const;

  // "EGL device 0 (NVIDIA ...)" or "EGL surfaceless platform", for --verbose.
  const std::string& platformDescription() const;
  // GL_VENDOR, GL_RENDERER, GL_VERSION as one line.
  std::string glDescription() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omnishadow
