#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli/view_options.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow render` accepts, as given on the command line.
struct RenderOptions {
  std::string scene;  // empty = the built-in demo scene
  std::string lights;
  bool noGltfLights = false;
  bool allowExternalUris = false;
  double maxMemoryMiB = 4096.0;
  std::string shadowPass = "auto";
  int sceneIndex = -1;
  ViewOptions view;
  std::vector<std::string> outputs;
  std::string aov;
  std::string aovLayers;   // comma-separated
  std::string dumpDepth;   // folder
  std::string lightViews;  // folder
  int lightViewSize = 512;
  std::string debugView = "none";
  std::string debugLight;
  float exposure = 0.0f;
  std::string shading = "pbr";
  int gpu = -1;
  bool verbose = false;
  bool stats = false;
};

void addRenderCommand(CLI::App& app, RenderOptions& options);

// Runs a render; returns the exit status. Throws InputError/RenderError to the caller.
int runRender(const RenderOptions& options);

}  // namespace omnishadow::cli
