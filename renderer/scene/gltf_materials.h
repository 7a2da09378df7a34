// Internal to the scene library: glTF images, textures and materials to Scene ones.
#pragma once

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// Fill Scene::images, ::textures and ::materials, one for one with the file's, in this order
// (textures refer to images, materials to textures).
void convertImages(Context& ctx);
void convertTextures(Context& ctx);
void convertMaterials(Context& ctx);

}  // namespace omnishadow::gltf_detail
