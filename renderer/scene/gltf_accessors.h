// Internal to the scene library: reading glTF accessors with every bound checked.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

enum class Normalize {
  AsFlagged,  // the accessor's `normalized` flag decides
  Integers,   // unsigned integer data is normalized (TEXCOORD_n and COLOR_n, glTF 3.7.2.1)
  Never,      // indices
};

struct AccessorValues {
  int components = 0;
  std::size_t count = 0;
  std::vector<double> values;  // count * components, element after element

  double get(std::size_t element, int component) const {
    return values[element * static_cast<std::size_t>(components) +
                  static_cast<std::size_t>(component)];
  }
};

int componentSize(int componentType);

// Returns the bytes of bufferViews[index] after checking that they lie inside their buffer.
const unsigned char* bufferViewData(const Context& ctx, const std::string& object, int index,
                                    std::size_t* length);

// Reads accessors[index] as doubles, element after element, with byteStride, normalization and
// sparse substitution applied. Throws InputError for anything outside its buffer.
AccessorValues readAccessor(Context& ctx, int index, Normalize normalize);

}  // namespace omnishadow::gltf_detail
