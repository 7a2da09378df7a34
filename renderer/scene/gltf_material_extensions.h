// Internal to the scene library: material and texture-slot extensions of glTF materials
// (KHR_texture_transform, KHR_materials_unlit, KHR_materials_pbrSpecularGlossiness,
// KHR_materials_transmission, KHR_materials_sheen).
#pragma once

#include <string>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// A texture slot for a textureInfo with `index` and `texCoord` whose KHR_texture_transform
// extension object is `transform` (nullptr when it has none): the index checked, the transform
// and its texCoord override applied. The empty slot, with a warning, for TEXCOORD sets other
// than 0 and 1; the empty slot for textures without a decodable image. Textures must have been
// converted.
TextureSlot makeTextureSlot(const Context& ctx, const std::string& object, int index, int texCoord,
                            const tinygltf::Value* transform);

// The KHR_texture_transform object of a textureInfo's extensions, or nullptr.
const tinygltf::Value* textureTransformOf(const tinygltf::ExtensionMap& extensions);

// The material extensions above of materials[index] into
// `material`, whose core fields are already filled.
void applyMaterialExtensions(const Context& ctx, std::size_t index, Material& material);

}  // namespace omnishadow::gltf_detail
