// libFuzzer target for glTF loading up to the CPU-side scene (no GL); scripts/fuzz.sh builds and
// runs it. loadGltf reads a file, so each input is written to a temporary folder of this process
// as input.glb (when it starts with the GLB magic) or input.gltf, and removed afterwards so
// that no input can see another's file. InputError is the expected answer to bad input; any
// other exception, a crash, a leak or undefined behaviour is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>
#include <typeinfo>

#include "renderer/core/errors.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/fuzz/fuzz_files.h"

namespace fs = std::filesystem;
using omnishadow::fuzz::TempFolder;
using omnishadow::fuzz::writeFile;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const TempFolder folder;
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const fs::path path = folder.path() / (glb ? "input.glb" : "input.gltf");
  writeFile(path, data, size);
  try {
    const omnishadow::Scene scene = omnishadow::loadGltf(path);
    (void)scene;
  } catch (const omnishadow::InputError&) {
    // Expected for invalid input.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_gltf: %s escaped loadGltf: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
  std::error_code ec;
  fs::remove(path, ec);
  return 0;
}
