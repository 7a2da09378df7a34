#pragma once

#include "renderer/output/image_writer.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// OpenEXR's worldToCamera and worldToNDC for the camera an image was rendered with, so that the
// CLI and the Python module write the same EXR headers.
ExrCameraAttributes exrCameraAttributes(const ViewCamera& camera);

}  // namespace omnishadow
