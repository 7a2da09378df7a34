#include "renderer/output/exr_camera.h"

#include <cstddef>

#include "renderer/view/camera_export.h"

namespace omnishadow {
namespace {

std::array<float, 16> columnMajor(const glm::dmat4& m) {
  std::array<float, 16> out{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      out[static_cast<std::size_t>(c * 4 + r)] = static_cast<float>(m[c][r]);
  return out;
}

}  // namespace

ExrCameraAttributes exrCameraAttributes(const ViewCamera& camera) {
  const CameraExport e = exportCamera(camera);
  return {columnMajor(e.worldToCameraExr), columnMajor(e.worldToNdc)};
}

}  // namespace omnishadow
