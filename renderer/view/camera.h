#pragma once

#include <glm/glm.hpp>
#include <optional>
#include <string>

#include "renderer/scene/scene.h"

namespace omnishadow {

// What the command line says about the camera and the image size.
struct CameraRequest {
  std::string select{};  // glTF camera name or index; empty = the first camera, if any
  std::optional<glm::vec3> eye{}, target{}, up{};
  std::optional<float> fovDegrees{};  // vertical field of view
  std::optional<int> width{}, height{};
};

// The camera a frame is rendered with, resolved against the scene.
struct ViewCamera {
  int width = 1280;
  int height = 720;
  glm::vec3 eye{0.0f};
  glm::mat4 view{1.0f};
  glm::mat4 projection{1.0f};  // reversed depth, [0,1] clip range (glClipControl ZERO_TO_ONE)
  bool orthographic = false;
  float znear = 0.01f;
  float zfar = 0.0f;        // 0 = infinite
  std::string description;  // e.g. "glTF camera 0 \"Main\"" or "automatic framing"
  int gltfCamera = -1;      // Scene::cameras entry it started from; -1 = automatic framing
  // Read back rows in GL order (row 0 = window bottom) instead of top first: light views use
  // it to match the GL texel layout of the cube map dumps.
  bool glRowOrder = false;
};

inline constexpr int kDefaultWidth = 1280;
inline constexpr int kDefaultHeight = 720;

// Picks the glTF camera (request.select, else the first), or frames the scene bounds when the
// file has none, then applies the overrides: --eye moves the camera keeping its orientation
// unless --target is also given; --target turns it to look there; --up sets the roll (+Y, or -Z
// when looking straight up or down, when --eye or --target is given without --up).
// Image size: --width/--height, else 1280x720, with the missing side following the camera's
// aspect ratio when the glTF camera has one. Throws InputError for an unknown camera or
// impossible overrides (eye == target, up parallel to the view direction, fov out of (0,180)),
// and for a glTF camera whose projection would not be finite (cameraProblem()).
ViewCamera resolveCamera(const Scene& scene, const CameraRequest& request);

// Reversed-depth projections for a [0,1] clip range. zfar = 0 gives an infinite far plane.
glm::mat4 reversedPerspective(float yfov, float aspect, float znear, float zfar);
glm::mat4 reversedOrthographic(float xmag, float ymag, float znear, float zfar);

// The row that gives a world point's depth along the view axis of `view` (a world-to-view
// matrix): dot(row, vec4(p, 1)) is minus p's view-space z, larger for farther points.
glm::vec4 viewDepthRow(const glm::mat4& view);

}  // namespace omnishadow
