// --gpu and --gpus against made-up EGL device lists (CI has no GPU): indices, cuda:N, auto, and
// how CUDA_VISIBLE_DEVICES, which numbers CUDA's devices but not EGL's, maps onto EGL devices.
#include "renderer/render/gpu_choice.h"

#include <gtest/gtest.h>

#include "renderer/core/errors.h"
#include "tests/support/input_error.h"

namespace omnishadow::gpu_choice_test {
namespace {

using test_support::inputError;

using Visible = std::optional<std::string>;

// EGL lists the GPUs in its own order: EGL 0 is CUDA device 2, EGL 1 CUDA 0, EGL 2 CUDA 1, and
// EGL 3 is Mesa's software device.
std::vector<GpuDevice> threeGpusAndSoftware() {
  std::vector<GpuDevice> devices(4);
  for (int i = 0; i < 4; ++i) devices[i].index = i;
  devices[0].renderer = "GPU C";
  devices[0].cuda = 2;
  devices[1].renderer = "GPU A";
  devices[1].cuda = 0;
  devices[2].renderer = "GPU B";
  devices[2].cuda = 1;
  devices[3].software = true;
  return devices;
}

// A Mesa machine: a GPU without CUDA numbers, and the software device.
std::vector<GpuDevice> mesaOnly() {
  std::vector<GpuDevice> devices(2);
  devices[0].index = 0;
  devices[0].drmNode = "/dev/dri/card0";
  devices[1].index = 1;
  devices[1].software = true;
  return devices;
}

int choose(const std::string& gpu, const std::vector<GpuDevice>& devices, Visible visible = {}) {
  return chooseGpu(parseGpuRequest(gpu), devices, visible);
}

TEST(GpuChoiceTest, ParsesIndicesCudaNumbersAndAuto) {
  EXPECT_EQ(parseGpuRequest("auto").kind, GpuRequest::Kind::Auto);
  const GpuRequest index = parseGpuRequest("3");
  EXPECT_EQ(index.kind, GpuRequest::Kind::Index);
  EXPECT_EQ(index.number, 3);
  const GpuRequest cuda = parseGpuRequest("cuda:12");
  EXPECT_EQ(cuda.kind, GpuRequest::Kind::Cuda);
  EXPECT_EQ(cuda.number, 12);
  for (const char* bad : {"", "-1", "1.5", "cuda:", "cuda:-1", "cuda:x", "gpu0", "0 ", "CUDA:0"})
    EXPECT_EQ(
        inputError([&] { parseGpuRequest(bad); }),
        std::string("--gpu ") + bad + ": expected auto, an EGL device index (0, 1, ...) or cuda:N")
        << bad;
}

TEST(GpuChoiceTest, AnIndexIsTheEglIndexAndAMissingOneNamesTheDevices) {
  EXPECT_EQ(choose("0", threeGpusAndSoftware()), 0);
  EXPECT_EQ(choose("3", threeGpusAndSoftware()), 3);
  // CUDA_VISIBLE_DEVICES does not renumber EGL indices.
  EXPECT_EQ(choose("1", threeGpusAndSoftware(), "2"), 1);
  EXPECT_EQ(inputError([] { choose("4", threeGpusAndSoftware()); }),
            "--gpu 4: there are only 4 EGL devices: 0 (GPU C, cuda:2), 1 (GPU A, cuda:0), "
            "2 (GPU B, cuda:1), 3 (software)");
  EXPECT_EQ(inputError([] { choose("2", mesaOnly()); }),
            "--gpu 2: there are only 2 EGL devices: 0 (/dev/dri/card0), 1 (software)");
  EXPECT_EQ(inputError([] { choose("0", {}); }),
            "--gpu 0: there are no EGL devices; leave --gpu out to use the surfaceless platform");
}

TEST(GpuChoiceTest, CudaNumbersGoThroughCudaVisibleDevices) {
  EXPECT_EQ(choose("cuda:0", threeGpusAndSoftware()), 1);
  EXPECT_EQ(choose("cuda:2", threeGpusAndSoftware()), 0);
  // The job sees CUDA devices 0 and 1, which are the machine's 2 and 0.
  EXPECT_EQ(choose("cuda:0", threeGpusAndSoftware(), "2,0"), 0);
  EXPECT_EQ(choose("cuda:1", threeGpusAndSoftware(), "2,0"), 1);
  EXPECT_EQ(inputError([] { choose("cuda:2", threeGpusAndSoftware(), "2,0"); }),
            "--gpu cuda:2: CUDA_VISIBLE_DEVICES=2,0 allows 2 CUDA devices");
  EXPECT_EQ(inputError([] { choose("cuda:3", threeGpusAndSoftware()); }),
            "--gpu cuda:3: no EGL device is CUDA device 3; the EGL devices are 0 (GPU C, cuda:2), "
            "1 (GPU A, cuda:0), 2 (GPU B, cuda:1), 3 (software)");
  EXPECT_EQ(inputError([] { choose("cuda:0", mesaOnly()); }),
            "--gpu cuda:0: no EGL device is CUDA device 0; the EGL devices are 0 "
            "(/dev/dri/card0), 1 (software)");
  EXPECT_EQ(inputError([] { choose("cuda:0", threeGpusAndSoftware(), "GPU-8a1b3c"); }),
            "--gpu cuda:0: CUDA_VISIBLE_DEVICES=GPU-8a1b3c names devices by UUID, which EGL does "
            "not tell; use numbers there or an EGL index here");
}

TEST(GpuChoiceTest, AutoFollowsCudaVisibleDevicesWhenItIsSet) {
  // Not set: the default order, whatever the devices.
  EXPECT_EQ(choose("auto", threeGpusAndSoftware()), -1);
  EXPECT_EQ(choose("auto", mesaOnly()), -1);
  // Set: the first device it allows, found by its CUDA number.
  EXPECT_EQ(choose("auto", threeGpusAndSoftware(), "1"), 2);
  EXPECT_EQ(choose("auto", threeGpusAndSoftware(), "2,1"), 0);
  EXPECT_EQ(choose("auto", threeGpusAndSoftware(), " 0 , 2"), 1);
  // Set to nothing (or CUDA's "hide everything"): the job has no GPU, so the software device.
  EXPECT_EQ(choose("auto", threeGpusAndSoftware(), ""), 3);
  EXPECT_EQ(choose("auto", threeGpusAndSoftware(), "-1"), 3);
  // Where no device tells a CUDA number, or the entries are UUIDs: the default order.
  EXPECT_EQ(choose("auto", mesaOnly(), "0"), -1);
  EXPECT_EQ(choose("auto", threeGpusAndSoftware(), "GPU-8a1b3c"), -1);
  // A number that no device has is a usage error, not a silent fall back to GPU 0.
  EXPECT_EQ(inputError([] { choose("auto", threeGpusAndSoftware(), "5"); }),
            "CUDA_VISIBLE_DEVICES=5: no EGL device is CUDA device 5; the EGL devices are 0 (GPU C, "
            "cuda:2), 1 (GPU A, cuda:0), 2 (GPU B, cuda:1), 3 (software); choose one with --gpu");
}

TEST(GpuChoiceTest, GpusAllOrAList) {
  using Indices = std::vector<int>;
  EXPECT_EQ(chooseGpus("all", threeGpusAndSoftware(), {}), (Indices{0, 1, 2}));
  EXPECT_EQ(chooseGpus("all", threeGpusAndSoftware(), "1,0"), (Indices{2, 1}));
  EXPECT_EQ(chooseGpus("all", mesaOnly(), {}), (Indices{0}));
  EXPECT_EQ(inputError([] { chooseGpus("all", threeGpusAndSoftware(), "1,7"); }),
            "--gpus all: CUDA_VISIBLE_DEVICES=1,7: no EGL device is CUDA device 7; the EGL devices "
            "are 0 (GPU C, cuda:2), 1 (GPU A, cuda:0), 2 (GPU B, cuda:1), 3 (software)");
  std::vector<GpuDevice> software(1);
  software[0].software = true;
  EXPECT_EQ(chooseGpus("all", software, {}), (Indices{0}));
  EXPECT_EQ(chooseGpus("2,0", threeGpusAndSoftware(), {}), (Indices{2, 0}));
  EXPECT_EQ(chooseGpus("cuda:0,cuda:1", threeGpusAndSoftware(), {}), (Indices{1, 2}));
  // Two workers on one device.
  EXPECT_EQ(chooseGpus("0,cuda:2", threeGpusAndSoftware(), {}), (Indices{0, 0}));
  EXPECT_EQ(inputError([] { chooseGpus("0,x", threeGpusAndSoftware(), {}); }),
            "--gpus 0,x: \"x\": expected all or a comma-separated list of EGL device indices or "
            "cuda:N");
  EXPECT_EQ(inputError([] { chooseGpus("auto", threeGpusAndSoftware(), {}); }),
            "--gpus auto: auto chooses one device; use all");
  EXPECT_EQ(inputError([] { chooseGpus("all", {}, {}); }),
            "--gpus all: there are no EGL devices; leave --gpus out to use the surfaceless "
            "platform");
}

}  // namespace
}  // namespace omnishadow::gpu_choice_test
