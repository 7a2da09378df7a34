#pragma once

#include <string>
#include <vector>

#include "renderer/render/render_settings.h"
#include "renderer/scene/light.h"
#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"
#include "renderer/view/shadow_plan.h"

namespace omnishadow {

// Everything about a frame that is decided before the GPU is touched.
struct FramePlan {
  ShadowAtlasPlan shadows;
  int debugLight = -1;  // DebugView::Depth: index into the lights of the light shown
  std::vector<std::string> warnings;
};

// Checks the frame against the device's limits and the settings, and plans its shadow maps.
// CPU only: throws InputError (a shadow resolution above the limits, shadow maps above
// settings.maxShadowMemoryMiB, an unknown --debug-light, more shadow groups than the shader
// samples) before anything is allocated.
FramePlan planFrame(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
                    const RenderSettings& settings, const RenderLimits& limits);

}  // namespace omnishadow
