#include "renderer/scene/gltf_extensions.h"

#include <algorithm>
#include <iterator>

namespace omnishadow {

namespace {

using enum ExtensionStatus;

// One line per extension. The loader's refusals and warnings (gltf_extension_policy.cpp),
// `omnishadow info` and the README's table follow it: an extension that becomes supported
// changes its status here, and the policy follows.
constexpr KnownExtension kKnownExtensions[] = {
    {"KHR_lights_punctual", Supported, ""},
    {"KHR_materials_emissive_strength", Supported, ""},
    {"KHR_texture_transform", Supported, ""},
    {"KHR_materials_unlit", Supported, ""},
    {"KHR_materials_pbrSpecularGlossiness", Supported, ""},
    {"KHR_texture_basisu", FallbackOnly, "the textures' PNG/JPEG fallback images"},
    {"EXT_texture_webp", Supported, ""},  // decoded with libwebp (webp_decoder)
    {"EXT_texture_avif", Supported, ""},  // decoded with libavif, loaded on first use
    {"MSFT_texture_dds", FallbackOnly, "the textures' PNG/JPEG fallback images"},
    // Geometry: decoded by gltf_draco and gltf_meshopt, dequantized by the accessor reader,
    // instances expanded by gltf_instancing.
    {"KHR_draco_mesh_compression", Supported, ""},
    {"EXT_meshopt_compression", Supported, ""},
    {"KHR_meshopt_compression", Supported, ""},
    {"KHR_mesh_quantization", Supported, ""},
    {"EXT_mesh_gpu_instancing", Supported, ""},
    // Materials beyond the core model.
    {"KHR_materials_clearcoat", Supported, ""},
    {"KHR_materials_sheen", Supported, ""},
    {"KHR_materials_transmission", Supported, ""},
    {"KHR_materials_volume", Supported, ""},
    {"KHR_materials_ior", Supported, ""},
    {"KHR_materials_specular", Supported, ""},
    {"KHR_materials_iridescence", Supported, ""},
    {"KHR_materials_anisotropy", Supported, ""},
    {"KHR_materials_dispersion", Supported, ""},
    {"KHR_materials_diffuse_transmission", Supported, ""},
    {"KHR_materials_variants", Supported, ""},
    // Everything else.
    {"KHR_animation_pointer", Supported, ""},
    {"KHR_node_visibility", Supported, ""},
    {"KHR_interactivity", NotSupported, "the static scene; its behaviour graphs do not run"},
    {"KHR_node_selectability", NotSupported, "every node (selection is for interactive viewers)"},
    {"KHR_xmp_json_ld", NotSupported, "the scene; its metadata is not read"},
    {"EXT_lights_image_based", NotSupported,
     "the punctual lights, the ambient and the lights file's environment"},
    {"MSFT_lod", NotSupported, "the full-detail meshes"},
};

}  // namespace

std::span<const KnownExtension> knownExtensions() {
  return kKnownExtensions;
}

const KnownExtension* findKnownExtension(std::string_view name) {
  const auto found = std::find_if(std::begin(kKnownExtensions), std::end(kKnownExtensions),
                                  [&](const KnownExtension& e) { return e.name == name; });
  return found == std::end(kKnownExtensions) ? nullptr : &*found;
}

}  // namespace omnishadow
