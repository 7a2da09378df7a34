#pragma once

#include <cstdlib>
#include <string_view>

namespace omnishadow {

// Whether this process runs under valgrind, whose preload library names itself in LD_PRELOAD.
// valgrind runs one thread at a time: helper threads that only save time (the memory warm-up,
// the relocation prefault) would compete with the render for it.
inline bool underValgrind() {
  const char* preload = std::getenv("LD_PRELOAD");
  return preload && std::string_view(preload).find("vgpreload") != std::string_view::npos;
}

}  // namespace omnishadow
