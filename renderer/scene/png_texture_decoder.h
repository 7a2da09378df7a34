// Internal to the scene library: the common PNG textures decoded with libdeflate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace omnishadow::gltf_detail {

// DEFLATE expands at most this many times (a 258-byte match coded in 2 bits): a PNG's rows
// cannot be longer than this times its compressed data.
constexpr std::uint64_t kMaxDeflateExpansion = 1032;

struct DecodedPng {
  bool ok = false;  // false: not a PNG this decoder takes; stb_image decodes it as before
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;  // width * height RGBA8, first row = top; alpha 255 for RGB
};

// Decodes the PNGs that textures almost always are: 8 bits per channel, RGB or RGBA, not
// interlaced, with only ancillary chunks beside IHDR, IDAT and IEND (no tRNS, no palette).
// libdeflate inflates the whole image data at once into the picture's own buffer, where the
// rows are unfiltered into RGBA: 2048^2 textures in less than half of stb_image's time, with no
// second buffer. The pixels are the file's, as stb_image decodes them. Anything else, a frame
// larger than maxSide per side or maxTexels in all included, and any data libdeflate finds
// damaged (a bad checksum, too few or too many bytes) or a row filter above 4, is left to
// stb_image (ok false), so that those files decode, or fail with the same message, as before.
DecodedPng decodePngTexture(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
                            std::uint64_t maxTexels);

}  // namespace omnishadow::gltf_detail
