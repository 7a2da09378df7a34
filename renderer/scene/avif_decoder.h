// Internal to the scene library: AVIF images (EXT_texture_avif) decoded with libavif.
#pragma once

#include <cstddef>
#include <cstdint>

#include "renderer/scene/decoded_image.h"

namespace omnishadow::gltf_detail {

// An ISO-BMFF file whose ftyp box names AVIF (`avif`, or `avis` for a sequence) as its major or
// a compatible brand.
bool isAvif(const unsigned char* bytes, std::size_t size);

// What an AVIF's container says, read without decoding the AV1 data (any size: the caller
// checks it).
ImageHeader readAvifHeader(const unsigned char* bytes, std::size_t size);

// Decodes a still AVIF (any bit depth, chroma subsampling and matrix; alpha 255 without) into
// RGBA8. Refuses sequences and frames larger than maxSide per side or maxTexels in all, from the
// container, before the AV1 data is decoded (libavif passes the limit on to its AV1 decoder).
//
// libavif brings the AV1 codecs (dav1d, libaom, rav1e, SVT-AV1, libgav1): linked, they cost
// every omnishadow process a few milliseconds of start-up, as much again as `--version` takes.
// So the library is loaded (dlopen, by its soname) the first time an AVIF is read; without it
// installed, AVIF images are refused with a message that names the package.
DecodedImage decodeAvif(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
                        std::uint64_t maxTexels);

}  // namespace omnishadow::gltf_detail
