// Internal to the scene library: what the glTF JSON says that tinygltf loses. tinygltf reads a
// field of the wrong type or sign as absent (byteStride -12, mode "x"), cannot tell an absent
// light range from 0, reports a bad required field without naming its object ("'count'
// property is not a positive integer."), and refuses what glTF allows: an index accessor
// without a bufferView (all zeros), a buffer without a uri that nothing uses (a placeholder),
// a WebP or AVIF image in a data: URI (which tinygltf takes for a file name).
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace omnishadow::gltf_detail {

// A primitive whose index accessor has no bufferView: hidden from tinygltf, restored after.
struct HiddenIndices {
  std::size_t mesh = 0, primitive = 0;
  int accessor = -1;
};

struct JsonReview {
  // The JSON to hand to tinygltf: empty when the original can be used as it is.
  std::string rewritten;
  std::vector<HiddenIndices> hiddenIndices;
  // What was set aside or drawn against the specification (a placeholder buffer, a WebP image
  // a core source names), without the file.
  std::vector<std::string> warnings;
};

// Checks `json` (a whole .gltf, or a .glb's JSON chunk; nesting already bounded) and throws
// InputError "<file>: <object>: <problem>" for values the glTF specification forbids that
// tinygltf would drop or report without their object. Text that is no JSON is left to
// tinygltf, which says where.
// `binary`: the JSON of a .glb, whose buffer 0 may be the BIN chunk (no uri).
JsonReview reviewGltfJson(std::string_view json, const std::string& file, bool binary);

// Puts the hidden index accessors back into the model tinygltf loaded.
void restoreHiddenIndices(tinygltf::Model& model, const std::vector<HiddenIndices>& hidden);

}  // namespace omnishadow::gltf_detail
