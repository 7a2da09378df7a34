// Internal to the scene library: EXT_meshopt_compression and KHR_meshopt_compression bufferViews.
#pragma once

#include <cstddef>
#include <string>

#include "renderer/scene/gltf_context.h"

namespace omnishadow::gltf_detail {

// The decoded bytes of bufferViews[index] (bufferView.byteLength of them, in *length) when it
// is meshopt-compressed, decoded on first use with meshoptimizer and its filters; nullptr when
// it is not compressed. Anything the decoder cannot take (bad mode, filter, stride, count,
// lengths, a stream that does not decode) is an InputError naming the bufferView and the
// extension; so is reading an uncompressed bufferView from a fallback buffer, which has no data.
const unsigned char* meshoptViewData(const Context& ctx, const std::string& object, int index,
                                     std::size_t* length);

}  // namespace omnishadow::gltf_detail
