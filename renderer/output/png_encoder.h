#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace omnishadow {

// How hard the PNG encoder works: libdeflate's level (1..12) and the row filter: one PNG
// filter type for every row (0 None, 1 Sub, 2 Up, 3 Average, 4 Paeth), or kAdaptivePngFilter:
// each row picks the type that leaves the smallest sum of absolute bytes (libpng's heuristic).
inline constexpr int kAdaptivePngFilter = -1;
struct PngEncoding {
  int level = 0;  // 0: kDefaultPngLevel
  int filter = 2;
};

// libdeflate level of writePng. With the Up filter it encodes a 1280x720 render in about 15 ms
// at 11% more bytes than libpng's adaptive filters at zlib level 6 (docs/performance.md, "PNG
// encoding", has the measurements).
inline constexpr int kDefaultPngLevel = 2;

// An 8-bit PNG file in memory: IHDR, one IDAT, IEND, nothing else (no time, text or gamma
// chunks), so identical pixels give identical bytes. 1..4 channels: grey, grey+alpha, RGB, RGBA
// with straight alpha; the first row is the top of the picture. The caller checks the sizes.
std::string encodePng(int width, int height, int channels, const std::vector<std::uint8_t>& pixels,
                      const PngEncoding& encoding = {});

// The same for a 16-bit grey PNG (instance and semantic masks), one sample per pixel.
std::string encodePng16(int width, int height, const std::vector<std::uint16_t>& pixels,
                        const PngEncoding& encoding = {});

}  // namespace omnishadow
