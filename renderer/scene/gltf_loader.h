#pragma once

#include <filesystem>

#include "renderer/scene/scene.h"

namespace omnishadow {

class DecodedImageCache;

struct GltfLoadOptions {
  int sceneIndex = -1;  // -1 = the file's default scene (or scene 0 when it names none)
  // Buffer and image URIs may name files outside the scene's folder (../, absolute paths).
  bool allowExternalUris = false;
  // KHR_materials_variants: the variant to draw, by name or index; empty = the primitives' own
  // materials. A file without that variant is an InputError.
  std::string materialVariant;
  // Pictures decoded by earlier loads that scenes still hold, taken instead of decoding the same
  // image bytes again, and where this load's decoded pictures go (not owned; null: none).
  DecodedImageCache* decodedImages = nullptr;
};

// Loads a .gltf (external or embedded buffers, data URIs) or .glb into CPU-side plain data:
// every triangle primitive of the chosen scene (strips and fans converted to lists, any index
// type widened to u32), node hierarchy flattened into world matrices, missing normals generated,
// tangents derived for normal-mapped materials, KHR_lights_punctual lights placed in world space.
// External files must lie in the scene's folder unless options.allowExternalUris; URIs with
// other schemes than data: are refused. Primitives with non-finite positions and nodes with
// non-finite transforms are skipped with a warning. Throws InputError ("<file>: <glTF object>:
// <problem>") for unreadable or invalid files; recoverable oddities (unsupported optional
// extensions, skins, morph targets) go to Scene::warnings.
Scene loadGltf(const std::filesystem::path& path, const GltfLoadOptions& options = {});

}  // namespace omnishadow
