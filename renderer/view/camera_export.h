#pragma once

#include <glm/glm.hpp>
#include <optional>

#include "renderer/view/camera.h"

namespace omnishadow {

// A rendered camera in the conventions other tools expect (camera sidecars, EXR headers,
// multi-view datasets).
//
// OpenGL convention (the renderer's and glTF's): the camera looks down its -Z, +Y up, +X right.
// OpenCV convention: the camera looks down its +Z, +Y down, +X right; a point X_cv in camera
// space lands at pixel u = fx X/Z + cx, v = fy Y/Z + cy, with v counted down from the image's top
// row and pixel (i, j) covering [i, i + 1) x [j, j + 1) (its center is at i + 0.5, j + 0.5).
struct CameraExport {
  int width = 0, height = 0;
  bool orthographic = false;
  // Pixels (perspective only; 0 for orthographic cameras).
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  double verticalFovDegrees = 0.0;  // perspective only
  double znear = 0.0;
  double zfar = 0.0;  // 0 = infinite
  glm::dmat4 worldToCameraGl{1.0}, cameraToWorldGl{1.0};
  glm::dmat4 worldToCameraCv{1.0}, cameraToWorldCv{1.0};
  glm::dmat4 projection{1.0};  // the renderer's: reversed depth, [0, 1] clip range
  // OpenEXR's worldToCamera: left-handed, +X right, +Y up, +Z the viewing direction.
  glm::dmat4 worldToCameraExr{1.0};
  glm::dmat4 worldToNdc{1.0};  // projection * worldToCameraGl (divide by w)
};

CameraExport exportCamera(const ViewCamera& camera);

}  // namespace omnishadow
