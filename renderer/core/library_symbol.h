#pragma once

// Functions of a library omnishadow loads with dlopen rather than links (libavif, Embree), looked
// up with the types their headers declare.

#include <dlfcn.h>

namespace omnishadow {

// Sets `function` to the symbol `name` of the library `handle`; false where it has none.
template <class F>
bool resolveSymbol(void* handle, const char* name, F& function) {
  function = reinterpret_cast<F>(::dlsym(handle, name));
  return function != nullptr;
}

}  // namespace omnishadow
