// libFuzzer target for batch manifests: parsing, every job field, and the confinement of output
// names to --out (scripts/fuzz.sh builds and runs it). Each input is written to a temporary
// folder of this process as manifest.json and read by collectJobs, which renders nothing.
// InputError is the expected answer to bad input; any other exception, a crash, a leak or
// undefined behaviour is a bug. A job that is accepted must write only below --out.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <typeinfo>
#include <vector>

#include "cli/batch_jobs.h"
#include "renderer/core/errors.h"
#include "tests/fuzz/fuzz_files.h"

namespace fs = std::filesystem;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const omnishadow::fuzz::TempFolder folder;
  const fs::path path = folder.path() / "manifest.json";
  omnishadow::fuzz::writeFile(path, data, size);
  omnishadow::cli::BatchDefaults defaults;
  defaults.out = folder.path() / "out";
  try {
    const std::vector<omnishadow::cli::BatchEntry> jobs =
        omnishadow::cli::collectJobs({path.string()}, defaults);
    const fs::path out = fs::weakly_canonical(defaults.out);
    for (const omnishadow::cli::BatchEntry& entry : jobs) {
      for (const fs::path& output : entry.job.outputFiles()) {
        const fs::path inside = omnishadow::cli::resolvedPath(output).lexically_relative(out);
        if (inside.empty() || *inside.begin() == "..") {
          std::fprintf(stderr, "fuzz_manifest: %s writes %s, outside --out\n", entry.name.c_str(),
                       output.c_str());
          std::abort();
        }
      }
    }
  } catch (const omnishadow::InputError&) {
    // Expected for invalid input.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_manifest: %s escaped collectJobs: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
  return 0;
}
