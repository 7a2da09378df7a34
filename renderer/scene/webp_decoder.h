// Internal to the scene library: WebP images (EXT_texture_webp) decoded with libwebp.
#pragma once

#include <cstddef>
#include <cstdint>

#include "renderer/scene/decoded_image.h"

namespace omnishadow::gltf_detail {

// A RIFF container whose form type is WEBP.
bool isWebp(const unsigned char* bytes, std::size_t size);

// What a WebP's headers say, read without decoding (libwebp's WebPGetFeatures).
ImageHeader readWebpHeader(const unsigned char* bytes, std::size_t size);

// Decodes a still WebP (lossy, lossless, with or without alpha; alpha 255 without) into RGBA8.
// Refuses, before anything is allocated, animations and frames larger than maxSide per side or
// maxTexels in all. libwebp decodes into memory of its own, which stays untouched past where
// damaged or missing data stops it, and the picture is copied out only once it is whole: a
// header that claims half a gigabyte of texels over a few bytes of data costs none of it.
DecodedImage decodeWebp(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
                        std::uint64_t maxTexels);

}  // namespace omnishadow::gltf_detail
