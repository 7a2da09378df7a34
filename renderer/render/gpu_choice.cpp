#include "renderer/render/gpu_choice.h"

#include <algorithm>
#include <charconv>
#include <sstream>

#include "renderer/core/errors.h"

namespace omnishadow {
namespace {

std::optional<int> parseNumber(const std::string& text) {
  int value = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 0) return std::nullopt;
  return value;
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> parts;
  std::istringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    part.erase(0, part.find_first_not_of(" \t"));
    part.erase(part.find_last_not_of(" \t") + 1);
    parts.push_back(part);
  }
  return parts;
}

const GpuDevice* withCuda(const std::vector<GpuDevice>& devices, int cuda) {
  for (const GpuDevice& device : devices)
    if (device.cuda == cuda) return &device;
  return nullptr;
}

bool anyCuda(const std::vector<GpuDevice>& devices) {
  return std::any_of(devices.begin(), devices.end(),
                     [](const GpuDevice& d) { return d.cuda.has_value(); });
}

// The physical CUDA numbers CUDA_VISIBLE_DEVICES allows, in its order; nullopt when an entry is
// no number (a GPU UUID or MIG name, which EGL cannot be matched with).
std::optional<std::vector<int>> visibleCudaNumbers(const std::string& value) {
  std::vector<int> numbers;
  for (const std::string& entry : splitList(value)) {
    // CUDA stops at the first invalid entry; "-1" hides every device.
    const std::optional<int> number = parseNumber(entry);
    if (!number) {
      if (entry == "-1" || entry.empty()) break;
      return std::nullopt;
    }
    numbers.push_back(*number);
  }
  return numbers;
}

std::string existing(const std::vector<GpuDevice>& devices) {
  if (devices.empty()) return "there are no EGL devices";
  return "the EGL devices are " + describeGpus(devices);
}

}  // namespace

GpuRequest parseGpuRequest(const std::string& text) {
  GpuRequest request;
  request.text = text;
  if (text == "auto") return request;
  if (const auto index = parseNumber(text)) {
    request.kind = GpuRequest::Kind::Index;
    request.number = *index;
    return request;
  }
  if (text.starts_with("cuda:"))
    if (const auto cuda = parseNumber(text.substr(5))) {
      request.kind = GpuRequest::Kind::Cuda;
      request.number = *cuda;
      return request;
    }
  throw InputError("--gpu " + text + ": expected auto, an EGL device index (0, 1, ...) or cuda:N");
}

std::string describeGpus(const std::vector<GpuDevice>& devices) {
  std::string text;
  for (const GpuDevice& d : devices) {
    std::string details = d.software ? "software" : d.renderer;
    if (details.empty()) details = d.drmNode;
    if (d.cuda)
      details += (details.empty() ? "" : ", ") + std::string("cuda:") + std::to_string(*d.cuda);
    text += (text.empty() ? "" : ", ") + std::to_string(d.index) +
            (details.empty() ? "" : " (" + details + ")");
  }
  return text;
}

int chooseGpu(const GpuRequest& request, const std::vector<GpuDevice>& devices,
              const std::optional<std::string>& cudaVisibleDevices) {
  switch (request.kind) {
    case GpuRequest::Kind::Index:
      if (request.number < static_cast<int>(devices.size())) return request.number;
      if (devices.empty())
        throw InputError("--gpu " + request.text +
                         ": there are no EGL devices; leave --gpu out to use the surfaceless "
                         "platform");
      throw InputError("--gpu " + request.text + ": there are only " +
                       std::to_string(devices.size()) + " EGL devices: " + describeGpus(devices));
    case GpuRequest::Kind::Cuda: {
      int cuda = request.number;
      if (cudaVisibleDevices) {
        const auto visible = visibleCudaNumbers(*cudaVisibleDevices);
        if (!visible)
          throw InputError("--gpu " + request.text +
                           ": CUDA_VISIBLE_DEVICES=" + *cudaVisibleDevices +
                           " names devices by UUID, which EGL does not tell; use numbers there "
                           "or an EGL index here");
        if (request.number >= static_cast<int>(visible->size()))
          throw InputError("--gpu " + request.text +
                           ": CUDA_VISIBLE_DEVICES=" + *cudaVisibleDevices + " allows " +
                           std::to_string(visible->size()) + " CUDA devices");
        cuda = (*visible)[static_cast<std::size_t>(request.number)];
      }
      if (const GpuDevice* device = withCuda(devices, cuda)) return device->index;
      throw InputError("--gpu " + request.text + ": no EGL device is CUDA device " +
                       std::to_string(cuda) + "; " + existing(devices));
    }
    case GpuRequest::Kind::Auto:
      break;
  }
  if (!cudaVisibleDevices) return -1;
  const auto visible = visibleCudaNumbers(*cudaVisibleDevices);
  if (!visible) return -1;
  if (visible->empty()) {
    for (const GpuDevice& device : devices)
      if (device.software) return device.index;
    return -1;
  }
  if (!anyCuda(devices)) return -1;
  if (const GpuDevice* device = withCuda(devices, visible->front())) return device->index;
  throw InputError("CUDA_VISIBLE_DEVICES=" + *cudaVisibleDevices +
                   ": no EGL device is CUDA device " + std::to_string(visible->front()) + "; " +
                   existing(devices) + "; choose one with --gpu");
}

std::vector<int> chooseGpus(const std::string& list, const std::vector<GpuDevice>& devices,
                            const std::optional<std::string>& cudaVisibleDevices) {
  std::vector<int> chosen;
  if (list == "all") {
    const auto visible =
        cudaVisibleDevices ? visibleCudaNumbers(*cudaVisibleDevices) : std::nullopt;
    if (visible && anyCuda(devices)) {
      for (int cuda : *visible) {
        const GpuDevice* device = withCuda(devices, cuda);
        if (!device)
          throw InputError("--gpus all: CUDA_VISIBLE_DEVICES=" + *cudaVisibleDevices +
                           ": no EGL device is CUDA device " + std::to_string(cuda) + "; " +
                           existing(devices));
        chosen.push_back(device->index);
      }
    } else {
      for (const GpuDevice& device : devices)
        if (!device.software) chosen.push_back(device.index);
    }
    if (chosen.empty())
      for (const GpuDevice& device : devices)
        if (device.software) chosen.push_back(device.index);
    if (chosen.empty())
      throw InputError("--gpus all: " + existing(devices) +
                       "; leave --gpus out to use the surfaceless platform");
    return chosen;
  }
  for (const std::string& entry : splitList(list)) {
    GpuRequest request;
    try {
      request = parseGpuRequest(entry);
    } catch (const InputError&) {
      throw InputError("--gpus " + list + ": \"" + entry +
                       "\": expected all or a comma-separated list of EGL device indices or "
                       "cuda:N");
    }
    if (request.kind == GpuRequest::Kind::Auto)
      throw InputError("--gpus " + list + ": auto chooses one device; use all");
    chosen.push_back(chooseGpu(request, devices, cudaVisibleDevices));
  }
  if (chosen.empty()) throw InputError("--gpus: expected all or a list of devices");
  return chosen;
}

}  // namespace omnishadow
