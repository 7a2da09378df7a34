#pragma once

#include "renderer/gl/raster_state.h"
#include "renderer/view/caster_culling.h"

namespace omnishadow {

// The scissor of exactly `rect`'s texels: clears and draws after it touch no other texel.
inline void scissorTo(const TexelRect& rect) {
  gl::Scissor{true, rect.x0, rect.y0, rect.x1 - rect.x0, rect.y1 - rect.y0}.apply();
}

}  // namespace omnishadow
