#pragma once

#include <vector>

#include "renderer/core/gpu_device.h"

namespace omnishadow {

// Every device of the EGL device platform, in EGL's order; empty when the platform is missing.
// With `probe`, a device whose EGL does not name its vendor and renderer gets a short-lived
// context to ask GL instead (slower: it loads the driver); a device where that fails keeps
// empty names.
std::vector<GpuDevice> listEglDevices(bool probe);

}  // namespace omnishadow
