#pragma once

#include <optional>
#include <string>

namespace omnishadow {

// One EGL device as `omnishadow devices` lists it and `--gpu` chooses among them. Plain data,
// so that the choice can be tested with made-up lists.
struct GpuDevice {
  int index = 0;       // the EGL device index (--gpu N)
  std::string vendor;  // e.g. "NVIDIA Corporation", "Mesa"; empty when unknown
  std::string
      renderer;        // e.g. "NVIDIA A100-SXM4-40GB/PCIe/SSE2", "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string driver;  // the driver's name or version, e.g. "4.5 (Core Profile) Mesa 22.3.6"
  std::string drmNode;      // "/dev/dri/card1"; empty for software devices
  std::string renderNode;   // "/dev/dri/renderD128"; empty when EGL does not say
  std::optional<int> cuda;  // the CUDA device number, where the driver tells (EGL_NV_device_cuda)
  bool software = false;    // Mesa's software device (EGL_MESA_device_software)
};

}  // namespace omnishadow
