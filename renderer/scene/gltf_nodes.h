// Internal to the scene library: the glTF node hierarchy, with its cameras and lights.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "renderer/scene/gltf_context.h"
#include "renderer/scene/gltf_loader.h"

namespace omnishadow::gltf_detail {

// Root nodes of the scene to draw, and how messages name that list.
std::pair<std::vector<int>, std::string> sceneRoots(const Context& ctx,
                                                    const GltfLoadOptions& options);

// Walks the hierarchy below `roots`: fills Scene::instances (converting each primitive once),
// ::cameras, ::lights and ::bounds. Materials must have been converted.
void addNodes(Context& ctx, const std::vector<int>& roots, const std::string& rootsObject);

}  // namespace omnishadow::gltf_detail
