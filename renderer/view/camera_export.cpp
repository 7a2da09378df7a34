#include "renderer/view/camera_export.h"

#include <cmath>

namespace omnishadow {

CameraExport exportCamera(const ViewCamera& camera) {
  CameraExport out;
  out.width = camera.width;
  out.height = camera.height;
  out.orthographic = camera.orthographic;
  out.znear = camera.znear;
  out.zfar = camera.zfar;
  out.projection = glm::dmat4(camera.projection);
  out.worldToCameraGl = glm::dmat4(camera.view);
  out.cameraToWorldGl = glm::inverse(out.worldToCameraGl);
  // OpenCV's camera space is OpenGL's turned half a turn about X: Y and Z flip.
  const glm::dmat4 flipYZ(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, -1, 0, 0), glm::dvec4(0, 0, -1, 0),
                          glm::dvec4(0, 0, 0, 1));
  out.worldToCameraCv = flipYZ * out.worldToCameraGl;
  out.cameraToWorldCv = glm::inverse(out.worldToCameraCv);
  const glm::dmat4 flipZ(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 1, 0, 0), glm::dvec4(0, 0, -1, 0),
                         glm::dvec4(0, 0, 0, 1));
  out.worldToCameraExr = flipZ * out.worldToCameraGl;
  out.worldToNdc = out.projection * out.worldToCameraGl;
  out.cx = 0.5 * camera.width;
  out.cy = 0.5 * camera.height;
  if (!camera.orthographic) {
    // NDC x = P00 X / -Z spans the width: u = (ndc + 1) / 2 * width.
    out.fx = 0.5 * camera.width * out.projection[0][0];
    out.fy = 0.5 * camera.height * out.projection[1][1];
    out.verticalFovDegrees = 2.0 * std::atan(1.0 / out.projection[1][1]) * 180.0 / M_PI;
  }
  return out;
}

}  // namespace omnishadow
