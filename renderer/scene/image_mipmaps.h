#pragma once

#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow {

// The mipmap levels below `base`, as glGenerateMipmap sizes them: level 1 is max(1, w/2) x
// max(1, h/2), and so on down to 1x1 (none for a 1x1 image). Each texel is the mean of the part
// of the level above that it covers (a 2x2 box where that level's sides are even), taken in
// linear light for sRGB images (`srgb`: RGB are sRGB codes; alpha is linear either way), from
// the unrounded level above, and rounded once.
//
// Made on the CPU instead of by glGenerateMipmap because llvmpipe compiles a blit shader per
// format for it on first use: 60-90 ms of every process that draws a texture (docs/performance.md).
std::vector<Image> mipmapChain(const Image& base, bool srgb);

}  // namespace omnishadow
