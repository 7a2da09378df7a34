#pragma once

#include <optional>
#include <string>

#include "cli/common_options.h"
#include "cli/view_options.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow verify` accepts, as given on the command line. The scene, lights and
// view options are those of `render`.
struct VerifyOptions {
  SceneInputOptions input;
  ViewOptions view;
  std::string light;     // empty = every light
  std::string maxError;  // fraction; empty = no bound (parsed here for a one-line message)
  std::string errorImage;
  float grazing = 0.05f;
  float edgeTexels = 3.0f;
  int sourceSamples = 64;
  int threads = 0;
  bool json = false;
  DeviceOptions device;
};

void addVerifyCommand(CLI::App& app, VerifyOptions& options);

// Renders the AOVs, casts exact shadow rays and prints the comparison (README, "omnishadow
// verify"). Returns 0, or 1 when an interior error rate exceeds --max-error. Throws
// InputError/RenderError to the caller.
int runVerify(const VerifyOptions& options);

}  // namespace omnishadow::cli
