// Internal to the scene library: the chunks of a PNG file, for the checks before decoding
// (gltf_file_safety.cpp) and the decoder (png_texture_decoder.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace omnishadow::gltf_detail {

// The 8-byte signature every PNG file starts with.
inline bool isPng(const unsigned char* bytes, std::size_t size) {
  return size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
}

inline std::uint32_t pngBe32(const unsigned char* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 |
         std::uint32_t{p[3]};
}

// Calls visit(type, data, length) for each chunk of a PNG file after its signature (PNG, section
// 5.3), in order, up to and including IEND, or until visit returns false. Returns the offset of
// the first chunk that does not lie within the `size` bytes (its length, type, data and CRC),
// or 0 when every chunk it came to does. A file without IEND ends in such a chunk.
template <class Visit>
std::size_t walkPngChunks(const unsigned char* bytes, std::size_t size, Visit visit) {
  for (std::size_t at = 8;;) {
    if (size < at || size - at < 12) return at;
    const std::uint32_t length = pngBe32(bytes + at);
    if (length > size - at - 12) return at;
    const std::string_view type(reinterpret_cast<const char*>(bytes + at + 4), 4);
    if (!visit(type, bytes + at + 8, length) || type == "IEND") return 0;
    at += 12 + std::size_t{length};
  }
}

}  // namespace omnishadow::gltf_detail
