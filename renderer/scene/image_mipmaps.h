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

// Whether a material samples a texture as sRGB color: base color, emissive and
// specular-glossiness (as the GPU scene uploads them; the other textures are linear).
// `visit(slot, srgb)` for each texture slot the material samples, in the upload's order.
template <typename Visit>
void forEachSampledTexture(const Material& material, const Visit& visit) {
  visit(material.baseColorTexture, true);
  if (material.specularGlossiness)
    visit(material.specularGlossinessTexture, true);
  else
    visit(material.metallicRoughnessTexture, false);
  visit(material.normalTexture, false);
  visit(material.occlusionTexture, false);
  visit(material.emissiveTexture, true);
  visit(material.transmissionTexture, false);
}

// Fills Image::mipmaps of every image a material samples, for the color space of its first
// use, on up to four threads: a single render makes them on its loading thread while the GL
// context opens, instead of in the upload (Sundial's 2048^2 texture: 8 ms).
void makeMipmapsAhead(Scene& scene);

}  // namespace omnishadow
