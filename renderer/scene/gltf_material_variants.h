// Internal to the scene library: KHR_materials_variants, the named sets of materials a file
// offers for its primitives (a product's colours, say), one of which a load may choose.
#pragma once

#include <string>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// Reads the file's variant names into ctx.scene.source.materialVariants and resolves
// `requested` (a name, or an index when no variant has that name; empty: the default
// materials) into ctx.materialVariant. Throws InputError for a malformed root extension and
// for a variant the file does not have.
void chooseMaterialVariant(Context& ctx, const std::string& requested);

// The material `primitive` is drawn with: `defaultMaterial` (its own), or the one its mappings
// give the chosen variant. Validates the mappings whether or not a variant is chosen, so that a
// file is refused or accepted alike either way. `object` names the primitive.
int primitiveMaterial(const Context& ctx, const tinygltf::Primitive& primitive,
                      const std::string& object, int defaultMaterial);

}  // namespace omnishadow::gltf_detail
