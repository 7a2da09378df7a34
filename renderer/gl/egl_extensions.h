#pragma once

#include <EGL/egl.h>

namespace omnishadow::gl {

// Whether the space-separated EGL extension list (eglQueryString) names `name` exactly; a null
// list (no display, or a query EGL refused) names none.
bool hasEglExtension(const char* list, const char* name);

// An EGL or GL entry point by name, as the function pointer type F; null where there is none.
template <typename F>
F loadEglProc(const char* name) {
  return reinterpret_cast<F>(eglGetProcAddress(name));
}

}  // namespace omnishadow::gl
