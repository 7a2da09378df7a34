#pragma once

#include <optional>
#include <string>
#include <vector>

#include "renderer/core/gpu_device.h"

namespace omnishadow {

// What --gpu asks for: "auto", an EGL device index "N", or the CUDA device "cuda:N".
struct GpuRequest {
  enum class Kind { Auto, Index, Cuda };
  Kind kind = Kind::Auto;
  int number = -1;   // the index or the CUDA device number
  std::string text;  // as given, for messages
};

// Throws InputError: "--gpu X: expected auto, an EGL device index or cuda:N".
GpuRequest parseGpuRequest(const std::string& text);

// The EGL device index to render on, or -1 for the default order (hardware devices first, then
// Mesa's software device, then the surfaceless platform). `devices` is what EGL lists;
// `cudaVisibleDevices` the value of CUDA_VISIBLE_DEVICES, when it is set.
//   N       device N; a usage error (InputError) naming the devices when there is none.
//   cuda:N  the device whose CUDA number is the N-th entry of CUDA_VISIBLE_DEVICES (N itself
//           when it is not set): CUDA numbers devices after applying CUDA_VISIBLE_DEVICES, EGL
//           before. A usage error when no device has that number.
//   auto    the device of the first CUDA_VISIBLE_DEVICES entry, as cuda:0 would choose, when it
//           is set to numbers and some device tells its CUDA number; the software device when
//           it is set but empty (the scheduler gave this job no GPU); else the default order.
int chooseGpu(const GpuRequest& request, const std::vector<GpuDevice>& devices,
              const std::optional<std::string>& cudaVisibleDevices);

// The devices for `batch --gpus`: "all" (every device but the software one, or the software one
// when there is nothing else; under CUDA_VISIBLE_DEVICES the devices it allows, in its order)
// or a comma-separated list of --gpu values; a device named twice gets two workers. Throws
// InputError like chooseGpu.
std::vector<int> chooseGpus(const std::string& list, const std::vector<GpuDevice>& devices,
                            const std::optional<std::string>& cudaVisibleDevices);

// "0 (NVIDIA A100, cuda:0), 1 (software)": the devices, for messages.
std::string describeGpus(const std::vector<GpuDevice>& devices);

}  // namespace omnishadow
