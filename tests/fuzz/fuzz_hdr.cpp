// libFuzzer target for the Radiance HDR decoder (scripts/fuzz.sh builds and runs it), which
// reads environment panoramas and `diff` inputs.
// InputError is the expected answer to bad input; any other exception, a crash, a leak or
// undefined behaviour is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>

#include "renderer/core/errors.h"
#include "renderer/output/radiance_hdr_decoder.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const omnishadow::FloatImage image = omnishadow::decodeRadianceHdr(bytes, "fuzz.hdr");
    (void)image;
  } catch (const omnishadow::InputError&) {
    // Expected for invalid input.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_hdr: %s escaped decodeRadianceHdr: %s\n", typeid(e).name(),
                 e.what());
    std::abort();
  }
  return 0;
}
