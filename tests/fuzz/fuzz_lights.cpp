// libFuzzer target for the lights file parser (scripts/fuzz.sh builds and runs it).
// InputError is the expected answer to bad input; any other exception, a crash, a leak or
// undefined behaviour is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/lights_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> warnings;
  try {
    const omnishadow::LightSetup setup = omnishadow::parseLights(text, "fuzz.json", warnings);
    (void)setup;
  } catch (const omnishadow::InputError&) {
    // Expected for invalid input.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_lights: %s escaped parseLights: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
  return 0;
}
