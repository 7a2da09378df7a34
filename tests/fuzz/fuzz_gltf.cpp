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

namespace {

namespace fs = std::filesystem;

// A folder of our own, made once: /dev/shm when there is one (no disk writes), else $TMPDIR.
class TempFolder {
 public:
  TempFolder() {
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0
                              ? fs::path("/dev/shm")
                              : fs::temp_directory_path();
    std::string pattern = (base / "omnishadow-fuzz-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      std::perror("fuzz_gltf: mkdtemp");
      std::abort();
    }
    path_ = pattern;
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

void writeFile(const fs::path& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr || (size > 0 && std::fwrite(data, 1, size, file) != size) ||
      std::fclose(file) != 0) {
    std::perror("fuzz_gltf: writing the input file");
    std::abort();
  }
}

}  // namespace

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
