#include "renderer/scene/gltf_compressed_json.h"

#include <nlohmann/json.hpp>

namespace omnishadow::gltf_detail {

using Json = nlohmann::json;

bool usesMeshopt(const Json& object) {
  const auto extensions = object.find("extensions");
  return extensions != object.end() && extensions->is_object() &&
         (extensions->contains("EXT_meshopt_compression") ||
          extensions->contains("KHR_meshopt_compression"));
}

namespace {

// Draco primitives keep their `indices` out of tinygltf's sight.
bool moveDracoIndices(Json& gltf, CompressionFixups& fixups) {
  bool changed = false;
  const auto meshes = gltf.find("meshes");
  if (meshes == gltf.end() || !meshes->is_array()) return false;
  for (std::size_t m = 0; m < meshes->size(); ++m) {
    Json& mesh = (*meshes)[m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) {
      continue;
    }
    Json& primitives = mesh["primitives"];
    for (std::size_t p = 0; p < primitives.size(); ++p) {
      Json& primitive = primitives[p];
      if (!primitive.is_object()) continue;
      const auto extensions = primitive.find("extensions");
      if (extensions == primitive.end() || !extensions->is_object() ||
          !extensions->contains("KHR_draco_mesh_compression")) {
        continue;
      }
      const auto indices = primitive.find("indices");
      if (indices == primitive.end() || !indices->is_number_integer()) continue;
      const auto value = indices->get<long long>();
      // Out-of-range values are left for tinygltf to refuse as before.
      if (value < 0 || value > 0x7FFFFFFF) continue;
      fixups.dracoIndices[{m, p}] = static_cast<int>(value);
      primitive.erase("indices");
      changed = true;
    }
  }
  return changed;
}

// A buffer without a uri that only compressed bufferViews refer to gets one byte of data.
bool fillPlaceholderBuffers(Json& gltf, bool binary, CompressionFixups& fixups) {
  const auto views = gltf.find("bufferViews");
  const auto buffers = gltf.find("buffers");
  if (views == gltf.end() || !views->is_array() || buffers == gltf.end() || !buffers->is_array()) {
    return false;
  }
  bool any = false;
  for (const Json& view : *views) any = any || (view.is_object() && usesMeshopt(view));
  if (!any) return false;
  bool changed = false;
  // In a .glb, buffer 0 without a uri is the BIN chunk.
  for (std::size_t b = binary ? 1 : 0; b < buffers->size(); ++b) {
    Json& buffer = (*buffers)[b];
    if (!buffer.is_object() || buffer.contains("uri")) continue;
    const auto length = buffer.find("byteLength");
    if (length == buffer.end() || !length->is_number()) continue;
    fixups.placeholderBuffers[b] = length->get<double>();
    buffer["byteLength"] = 1;
    buffer["uri"] = "data:application/octet-stream;base64,AA==";
    changed = true;
  }
  return changed;
}

// KHR_animation_pointer channels have a target without a node, which tinygltf 2.7 refuses (it
// then drops the channel): they get node -1, which the loader reads as "no node".
bool markPointerTargets(Json& gltf) {
  bool changed = false;
  const auto animations = gltf.find("animations");
  if (animations == gltf.end() || !animations->is_array()) return false;
  for (Json& animation : *animations) {
    if (!animation.is_object()) continue;
    const auto channels = animation.find("channels");
    if (channels == animation.end() || !channels->is_array()) continue;
    for (Json& channel : *channels) {
      if (!channel.is_object()) continue;
      const auto target = channel.find("target");
      if (target == channel.end() || !target->is_object() || target->contains("node")) continue;
      (*target)["node"] = -1;
      changed = true;
    }
  }
  return changed;
}

}  // namespace

std::optional<std::string> rewriteCompressedJson(std::string_view json, bool binary,
                                                 CompressionFixups& fixups) {
  if (json.find("KHR_draco_mesh_compression") == std::string_view::npos &&
      json.find("_meshopt_compression") == std::string_view::npos &&
      json.find("KHR_animation_pointer") == std::string_view::npos) {
    return std::nullopt;
  }
  Json gltf = Json::parse(json, nullptr, /*allow_exceptions=*/false);
  if (!gltf.is_object()) return std::nullopt;
  CompressionFixups found;
  const bool draco = moveDracoIndices(gltf, found);
  const bool meshopt = fillPlaceholderBuffers(gltf, binary, found);
  const bool pointers = markPointerTargets(gltf);
  if (!draco && !meshopt && !pointers) return std::nullopt;
  fixups = std::move(found);
  return gltf.dump();
}

}  // namespace omnishadow::gltf_detail
