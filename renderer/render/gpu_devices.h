#pragma once

#include <vector>

#include "renderer/core/gpu_device.h"

namespace omnishadow {

// Every EGL device, in EGL's order (implemented with the Renderer, where GL may be seen). With
// `probe`, names EGL does not tell come from a short-lived context on each device.
std::vector<GpuDevice> listGpuDevices(bool probe);

}  // namespace omnishadow
