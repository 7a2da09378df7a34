// Internal to the scene library: what the glTF loader's conversion steps share.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <glm/glm.hpp>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/scene/decoded_image_cache.h"
#include "renderer/scene/gltf_compressed_json.h"
#include "renderer/scene/scene.h"

namespace omnishadow::gltf_detail {

// "array[index]", the way messages name a glTF object.
std::string at(std::string_view array, std::size_t index);
// The file's name for an object, or `kind` and its index ("skin0") where it gives none, so that
// every object has a name messages and outputs can use.
std::string nameOrDefault(const std::string& name, std::string_view kind, std::size_t index);
// "1 mesh", "2 meshes".
std::string plural(std::size_t count, std::string_view noun);
// The lines of `text` with trailing blanks removed, empty ones left out.
std::vector<std::string> nonEmptyLines(const std::string& text);

// State shared by the conversion steps: the parsed file, the scene being filled, and the
// message conventions ("<file>: <glTF object>: <problem>").
struct Context {
  std::string file;
  const tinygltf::Model& model;
  Scene& scene;
  std::size_t countWithoutBufferView = 0;  // elements read so far from accessors without one
  // Geometry extensions (gltf_draco, gltf_meshopt, gltf_compressed_json):
  bool quantized = false;      // KHR_mesh_quantization declared: integer positions, normals, ...
  CompressionFixups fixups{};  // what the reader changed so that tinygltf parses the file
  // Decoded meshopt bufferViews by index, filled on first use (bufferViewData is const).
  mutable std::map<int, std::vector<unsigned char>> meshoptViews{};
  // Draco-decoded data of the primitive being converted, by accessor index, laid out tightly
  // as each accessor describes; read instead of the accessor's (absent) bufferView.
  std::map<int, std::vector<unsigned char>> dracoAccessors{};
  std::string primitive{};   // "meshes[m].primitives[p]" while one is converted, for decoders
  int materialVariant = -1;  // KHR_materials_variants: the chosen variant, -1 for none
  DecodedImageCache* decodedImages = nullptr;  // GltfLoadOptions::decodedImages

  [[noreturn]] void fail(const std::string& object, const std::string& problem) const {
    throw InputError(file + ": " + object + ": " + problem);
  }
  void warn(const std::string& message) const { scene.warnings.push_back(file + ": " + message); }

  // Validates a reference from `object` to model array `array` of `size` elements.
  void checkIndex(const std::string& object, std::string_view array, int index,
                  std::size_t size) const {
    if (index < 0 || static_cast<std::size_t>(index) >= size) {
      fail(object, std::string(array) + " " + std::to_string(index) +
                       " is out of range (the file has " + plural(size, array) + ")");
    }
  }
};

// The first N numbers of a glTF array property, or `fallback` when it does not have N.
template <glm::length_t N>
glm::vec<N, float> factor(const std::vector<double>& values, glm::vec<N, float> fallback) {
  if (values.size() != N) return fallback;
  glm::vec<N, float> out;
  for (glm::length_t i = 0; i < N; ++i)
    out[i] = static_cast<float>(values[static_cast<std::size_t>(i)]);
  return out;
}

}  // namespace omnishadow::gltf_detail
