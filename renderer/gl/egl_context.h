#pragma once

#include <memory>
#include <string>
#include <vector>

namespace omnishadow {

struct EglContextOptions {
  int gpuIndex = -1;   // EGL device index (--gpu); -1 = hardware devices first, then software
  bool debug = false;  // debug context + KHR_debug messages printed to stderr (--verbose)
};

// Headless OpenGL 4.5 core context, current on the calling thread for its lifetime. No window,
// no surface, no X: rendering goes into the caller's framebuffer objects.
// Tries the EGL device platform (hardware devices first, then Mesa's software device), then
// Mesa's surfaceless platform. Throws RenderError listing every attempt and what EGL said.
class EglContext {
 public:
  explicit EglContext(const EglContextOptions& options);
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // "EGL device 0 (NVIDIA ...)" or "EGL surfaceless platform", for --verbose.
  const std::string& platformDescription() const;
  // GL_VENDOR, GL_RENDERER, GL_VERSION as one line.
  std::string glDescription() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omnishadow
