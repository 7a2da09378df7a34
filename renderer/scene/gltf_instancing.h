// Internal to the scene library: EXT_mesh_gpu_instancing.
#pragma once

#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// The node-local transforms of the instances that nodes[nodeIndex]'s EXT_mesh_gpu_instancing
// places (translation * rotation * scale per instance, from its TRANSLATION, ROTATION and SCALE
// accessors, float or quantized integers), to be applied before the node's world transform;
// empty when the node has no such extension. Accessors of the wrong type or of differing counts
// are an InputError naming the node and the extension.
std::vector<glm::mat4> instanceTransforms(Context& ctx, std::size_t nodeIndex);

}  // namespace omnishadow::gltf_detail
