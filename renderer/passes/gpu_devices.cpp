#include "renderer/render/gpu_devices.h"

#include "renderer/gl/egl_devices.h"

namespace omnishadow {

std::vector<GpuDevice> listGpuDevices(bool probe) {
  return listEglDevices(probe);
}

}  // namespace omnishadow
