#pragma once

// Paying LLVM's once-per-process start-up on another thread before the first frame.
//
// Mesa's llvmpipe compiles each shader and each triangle-setup function with LLVM at the first
// draw that needs it. A process's first compilation takes about 7 ms more than later ones of
// the same size: LLVM's code generator builds its registries and tables once (a trivial
// function: 10-11 ms the first time, 3.4 ms after). A first frame paid that in its shadow pass:
// Box's first setup function took 12 ms, the later ones 4-6. Compiling one trivial function
// through LLVM's C API on a spare core, while the renderer's thread links shaders and uploads
// the scene, pays it there (EglContext::startLlvmWarmup(), Renderer::warmUpLlvm()). Each
// compilation has its own LLVM context, as llvmpipe's have, and LLVM initializes its shared
// state once whichever thread gets there first.

#include <string>
#include <thread>
#include <vector>

namespace omnishadow {

class LlvmWarmup {
 public:
  // Starts the thread when one of `libraries` (file names, as loadedLibraries() gives them) is
  // LLVM's shared library; nothing otherwise, nor under valgrind.
  explicit LlvmWarmup(const std::vector<std::string>& libraries);
  ~LlvmWarmup();  // waits for the thread
  LlvmWarmup(const LlvmWarmup&) = delete;
  LlvmWarmup& operator=(const LlvmWarmup&) = delete;

  bool started() const { return thread_.joinable() || finished_; }
  // Waits for the thread; then whether the function it compiled ran and returned what it should
  // (false when nothing was started, or LLVM refused: no native target, a missing symbol).
  bool wait();

  // The first of `libraries` that is LLVM's shared library (libLLVM-15.so.1, libLLVM.so.18.1),
  // or an empty string.
  static std::string llvmLibrary(const std::vector<std::string>& libraries);

 private:
  std::thread thread_;
  bool finished_ = false;
  bool compiled_ = false;
};

}  // namespace omnishadow
