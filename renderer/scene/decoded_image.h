// Internal to the scene library: what the decoders of the texture-extension formats (WebP,
// AVIF) report of an image's header and give of its picture.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace omnishadow::gltf_detail {

// What a file's headers say, read without decoding its picture.
struct ImageHeader {
  bool ok = false;  // false: `error` says why
  std::uint32_t width = 0, height = 0;
  bool animated = false;  // several frames (the extensions take still images)
  std::string error;
};

struct DecodedImage {
  bool ok = false;
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;  // width * height RGBA8, not premultiplied, first row = top
  std::string error;                // why not, when !ok
};

}  // namespace omnishadow::gltf_detail
