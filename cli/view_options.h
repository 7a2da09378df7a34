#pragma once

#include <optional>
#include <string>

#include "renderer/view/camera.h"

namespace CLI {
class App;
}

namespace omnishadow::cli {

// The camera and image-size options that `render`, `batch` and `verify` share, as given on the
// command line.
struct ViewOptions {
  std::string camera;           // glTF camera by name or index; empty = the first
  std::string eye, target, up;  // "x,y,z"; empty = not given
  std::optional<float> fov;
  std::optional<int> width, height;
};

// Adds --camera, --eye, --target, --up, --fov, --width and --height to a subcommand.
void addViewOptions(CLI::App& command, ViewOptions& options);

// The camera the options ask for; InputError naming the option for a malformed vector.
CameraRequest cameraRequest(const ViewOptions& options);

}  // namespace omnishadow::cli
