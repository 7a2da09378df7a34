// Internal to the scene library: glTF mesh primitives to Scene meshes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// meshes[meshIndex].primitives[primIndex] as a triangle list with normals (generated when
// missing) and tangents (generated for normal-mapped materials), or as points or line pairs;
// nullopt, with a warning, for primitives that are not drawn (no or non-finite POSITION).
// Materials must have been converted.
std::optional<Mesh> convertPrimitive(Context& ctx, std::size_t meshIndex, std::size_t primIndex);

// The primitive's triangle list as convertPrimitive() makes it (strips and fans converted, a
// partial last triangle dropped), as indices of the file's vertices: where each vertex of a
// mesh whose flat normals were generated comes from.
std::vector<std::uint32_t> fileTriangleIndices(Context& ctx, std::size_t meshIndex,
                                               std::size_t primIndex);

}  // namespace omnishadow::gltf_detail
