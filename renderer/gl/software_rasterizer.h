#pragma once

#include <string_view>

namespace omnishadow::gl {

// Whether a GL_RENDERER string names Mesa's llvmpipe, which rasterizes on the CPU's cores: the
// renderer draws some passes differently there (the depth pre-pass, a second context for the
// shadow maps), each where it was measured to pay.
inline bool isLlvmpipe(std::string_view glRenderer) {
  return glRenderer.find("llvmpipe") != std::string_view::npos;
}

}  // namespace omnishadow::gl
