// Internal to the scene library: what the loader keeps for posing (renderer/scene/scene_rig.h):
// nodes, skins, morph targets, animations.
#pragma once

#include <cstddef>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// Fills Scene::rig's nodes, skins and animations from the file. Animation channels that cannot
// be played (unknown path, keyframes out of order, counts that do not match) are left out with
// a warning; references out of range and unreadable accessors throw InputError.
void readRig(Context& ctx);

// Whether instances of meshes[meshIndex].primitives[primIndex] placed by nodes[nodeIndex] are
// computed by posing (skinned or morphed).
bool isDeformed(const Context& ctx, std::size_t nodeIndex, std::size_t meshIndex,
                std::size_t primIndex);

// Records the source data of Scene::instances[instance], a deformed instance (isDeformed())
// whose Scene mesh is its own. readRig() must have run.
void addDeformedInstance(Context& ctx, std::size_t nodeIndex, std::size_t meshIndex,
                         std::size_t primIndex, int instance);

}  // namespace omnishadow::gltf_detail
