#pragma once

namespace omnishadow::gl {

// The state every context of the renderer starts from: reversed depth with a [0,1] clip range
// (float depth stays precise from near to far) and seamless cube map filtering. A second
// context (ShadowWorker) must rasterize exactly as the first, so both call this.
void applyContextDefaults();

}  // namespace omnishadow::gl
