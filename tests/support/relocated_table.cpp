// A library whose loading is mostly relocation: a table of 2^17 pointers into its own text
// (1 MiB of .data.rel.ro, one relative relocation each), for tests/relocation_prefault_test.cpp.
#include <array>
#include <cstddef>

namespace {

constexpr std::size_t kTextBytes = 4096;
constexpr std::size_t kEntries = std::size_t{1} << 17;

}  // namespace

extern "C" {

// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): its address is the point
char omnishadow_relocated_text[kTextBytes] = {};

extern const std::size_t omnishadow_relocated_entries;
extern const std::size_t omnishadow_relocated_text_bytes;
const std::size_t omnishadow_relocated_entries = kEntries;
const std::size_t omnishadow_relocated_text_bytes = kTextBytes;

extern const std::array<const char*, kEntries> omnishadow_relocated_table;
constinit const std::array<const char*, kEntries> omnishadow_relocated_table = [] {
  std::array<const char*, kEntries> table{};
  for (std::size_t i = 0; i < kEntries; ++i)
    table[i] = omnishadow_relocated_text + (i * 7919) % kTextBytes;
  return table;
}();
}
