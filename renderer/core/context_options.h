#pragma once

namespace omnishadow {

// How to make the headless GL context: the renderer's public options, handed unchanged to the
// EGL layer, so the two cannot drift apart.
struct ContextOptions {
  int gpuIndex = -1;   // EGL device index (--gpu); -1 = hardware devices first, then software
  bool debug = false;  // debug context + KHR_debug messages printed to stderr (--verbose)
};

}  // namespace omnishadow
