#include "cli/view_options.h"

#include <CLI/CLI.hpp>

#include "cli/render_job.h"

namespace omnishadow::cli {

void addViewOptions(CLI::App& command, ViewOptions& o) {
  command.add_option("--camera", o.camera, "glTF camera by name or index (default: the first)");
  command.add_option("--eye", o.eye, "Camera position x,y,z (world units)");
  command.add_option("--target", o.target, "Point the camera looks at, x,y,z");
  command.add_option("--up", o.up, "Camera up vector x,y,z");
  command.add_option("--fov", o.fov, "Vertical field of view in degrees");
  command.add_option("--width", o.width, "Image width in pixels (default 1280)")
      ->check(CLI::Range(1, 16384));
  command
      .add_option("--height", o.height,
                  "Image height in pixels (default 720, or from the camera's aspect ratio)")
      ->check(CLI::Range(1, 16384));
}

CameraRequest cameraRequest(const ViewOptions& o) {
  CameraRequest request;
  request.select = o.camera;
  request.eye = parseVec3("--eye", o.eye);
  request.target = parseVec3("--target", o.target);
  request.up = parseVec3("--up", o.up);
  request.fovDegrees = o.fov;
  request.width = o.width;
  request.height = o.height;
  return request;
}

}  // namespace omnishadow::cli
