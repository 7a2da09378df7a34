#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli/common_options.h"
#include "cli/frame_set.h"
#include "cli/view_options.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow render` accepts, as given on the command line.
struct RenderOptions {
  SceneInputOptions input;
  ViewOptions view;
  std::vector<std::string> outputs;
  std::string aov;
  // --masks stem
  std::string masks;
  // --aa
  int antialiasing = 1;
  std::string aovLayers;   // comma-separated
  std::string dumpDepth;   // folder
  std::string lightViews;  // folder
  int lightViewSize = 512;
  std::string debugView = "none";
  std::string debugLight;
  float exposure = 0.0f;
  std::string shading = "pbr";
  int repeat = 0;  // --repeat: frames timed after the written one (steady_frames.h)
  DeviceOptions device;
  FrameSetOptions frames;  // sequences, camera sets, the camera sidecar
};

void addRenderCommand(CLI::App& app, RenderOptions& options);

// Runs a render; returns the exit status. Throws InputError/RenderError to the caller.
int runRender(const RenderOptions& options);

}  // namespace omnishadow::cli
