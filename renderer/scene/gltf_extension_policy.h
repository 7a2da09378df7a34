// Internal to the scene library: the loader's policy for the extensions a file lists, and for
// the texture-image extensions: WebP and AVIF drawn, KTX2 and DDS images never decoded.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// Refuses (InputError, "extensionsRequired: X is not supported...") the first required
// extension the loader cannot draw; warns once for each used one it draws without, saying what
// is drawn instead. Returns every listed extension, for SourceSummary::extensions.
std::vector<ExtensionUse> checkExtensions(const Context& ctx);

// The first of `required` that the loader cannot draw (as checkExtensions would refuse it), or
// an empty string.
std::string firstUnsupportedRequired(const std::vector<std::string>& required);

// The image texture `index` draws: its EXT_texture_avif or else EXT_texture_webp `source` when
// it has one (checked to be an image of the file), else its core `source` (-1: none).
int drawnImage(const Context& ctx, std::size_t index);

// For each image of the file: true when no texture draws it, but some texture names it, so
// that it is never decoded: the KTX2 (KHR_texture_basisu), AVIF and DDS images, whose textures
// draw their fallback `source`, and the fallbacks of the textures that draw AVIF or WebP.
std::vector<bool> imagesNotDecoded(const Context& ctx);

// A texture without a core `source`, an AVIF or a WebP one, whose only image comes through an
// extension whose images are not decoded, cannot be drawn: fails naming the extension. Does nothing
// for other textures.
void requireFallbackSource(const Context& ctx, std::size_t texture);

}  // namespace omnishadow::gltf_detail
