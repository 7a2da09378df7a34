// Internal to the scene library: reading a .gltf or .glb file into a tinygltf model.
#pragma once

#include <tiny_gltf.h>

#include <filesystem>
#include <string>
#include <vector>

#include "renderer/scene/gltf_compressed_json.h"

namespace omnishadow::gltf_detail {

// Parses `path` (named `file` in messages) as JSON glTF or, by its content, binary glTF, with
// external files read through a UriPolicy. Tolerated oddities go to `warnings`; anything else
// throws InputError naming the field or object at fault where tinygltf does not. What had to be
// changed for tinygltf to parse compressed geometry goes to `fixups`.
tinygltf::Model readModel(const std::filesystem::path& path, const std::string& file,
                          std::vector<std::string>& warnings, bool* isBinary,
                          bool allowExternalUris, CompressionFixups& fixups);

}  // namespace omnishadow::gltf_detail
