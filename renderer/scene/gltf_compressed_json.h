// Internal to the scene library: what tinygltf cannot parse in files with compressed geometry,
// and in animations with KHR_animation_pointer channels.
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>

namespace omnishadow::gltf_detail {

// tinygltf 2.7 refuses two things the compression extensions do by design: a Draco primitive's
// index accessor has no bufferView, and a meshopt fallback buffer has no data (no uri, and in a
// .glb not the BIN chunk either). The reader takes both out of the JSON before tinygltf sees it
// and remembers them here. (It also gives KHR_animation_pointer channel targets, which have no
// node, node -1, which tinygltf accepts and the loader reads as "no node".)
struct CompressionFixups {
  // KHR_draco_mesh_compression primitives' `indices`, by (mesh, primitive).
  std::map<std::pair<std::size_t, std::size_t>, int> dracoIndices;
  // Buffers without data that compressed bufferViews decode into (now 1 byte long), with the
  // byteLength the file gave them.
  std::map<std::size_t, double> placeholderBuffers;
};

// Whether a glTF object (a bufferView) has EXT_ or KHR_meshopt_compression: its `buffer` is
// then a fallback that may have no data.
bool usesMeshopt(const nlohmann::json& object);

// The JSON text of a glTF file rewritten as described above, or nullopt when it needs no
// rewriting (it uses none of those extensions, or is not JSON that nlohmann parses: then tinygltf's
// own message is the one to give). `binary`: the JSON is a .glb's, whose buffer 0 is its BIN
// chunk.
std::optional<std::string> rewriteCompressedJson(std::string_view json, bool binary,
                                                 CompressionFixups& fixups);

}  // namespace omnishadow::gltf_detail
