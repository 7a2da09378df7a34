// Internal to the scene library: the loader's policy for the extensions a file lists, and the
// texture-image extensions (KTX2, WebP, ...) whose images it never decodes.
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

// For each image of the file: true when only texture extensions (KHR_texture_basisu and the
// like) reference it, so that it is never decoded and textures use their fallback `source`.
std::vector<bool> imagesOnlyInExtensions(const Context& ctx);

// A texture without a core `source` whose only image comes through such an extension cannot be
// drawn: fails naming the extension. Does nothing for other textures.
void requireFallbackSource(const Context& ctx, std::size_t texture);

}  // namespace omnishadow::gltf_detail
