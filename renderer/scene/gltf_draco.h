// Internal to the scene library: KHR_draco_mesh_compression primitives.
#pragma once

#include <cstddef>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// The accessor that holds meshes[m].primitives[p]'s indices: its `indices`, or for a Draco
// primitive the one the reader took out of tinygltf's sight; -1 for none.
int indicesAccessor(const Context& ctx, std::size_t meshIndex, std::size_t primIndex);

// Decodes the primitive's Draco data, if it has any, into ctx.dracoAccessors: each attribute the
// extension names, and the indices, in the layout their accessors describe, so that they are
// read and checked like uncompressed data. A stream that does not decode, or whose output does
// not match the accessors (count, components, values that do not fit the component type), is an
// InputError naming the primitive and the extension.
void decodeDraco(Context& ctx, std::size_t meshIndex, std::size_t primIndex);

}  // namespace omnishadow::gltf_detail
