#include "renderer/scene/png_texture_decoder.h"

#include <libdeflate.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>

#include "renderer/scene/png_chunks.h"

namespace omnishadow::gltf_detail {

namespace {

struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// The file's layout, when it is one decodePngTexture takes.
struct Layout {
  std::uint32_t width = 0, height = 0;
  int channels = 0;                                                // 3 (RGB) or 4 (RGBA)
  std::vector<std::pair<const unsigned char*, std::size_t>> data;  // the IDAT chunks, in order
};

bool parse(const unsigned char* bytes, std::size_t size, Layout& layout) {
  if (!isPng(bytes, size)) return false;
  bool header = false, taken = true, ended = false;
  const auto visit = [&](std::string_view type, const unsigned char* data, std::uint32_t length) {
    if (!header) {
      // IHDR: width, height, bit depth, colour type, compression, filter, interlace.
      taken = type == "IHDR" && length == 13 && data[8] == 8 && (data[9] == 2 || data[9] == 6) &&
              data[10] == 0 && data[11] == 0 && data[12] == 0;
      if (taken) {
        layout.width = pngBe32(data);
        layout.height = pngBe32(data + 4);
        layout.channels = data[9] == 6 ? 4 : 3;
      }
      header = true;
    } else if (type == "IDAT") {
      layout.data.emplace_back(data, length);
    } else if (type == "IEND") {
      ended = true;
    } else if ((type[0] & 0x20) == 0 || type == "tRNS") {
      taken = false;  // a critical chunk (PLTE, CgBI, ...) or transparency: stb's to handle
    }
    return taken;
  };
  // Every chunk within the data, up to IEND.
  return walkPngChunks(bytes, size, visit) == 0 && taken && ended && !layout.data.empty();
}

// One row's bytes from its filtered form (PNG, section 9), into RGBA: each byte plus the
// filter's predictor from the bytes to its left (a), above (b) and above-left (c), zero beyond
// the picture, modulo 256. Sub, Average and Paeth chain from pixel to pixel, so the left and
// above-left pixels must stay in registers: with the channel loop rolled, GCC kept them in
// memory, and Avocado's 2048^2 textures decoded 10-25% slower.
template <int N, class Predictor>
void unfilterRow(const unsigned char* in, const unsigned char* up, unsigned char* out,
                 std::size_t width, Predictor predictor) {
  std::array<unsigned, N> left{}, upLeft{};
  for (std::size_t x = 0; x < width; ++x)
#pragma GCC unroll 4
    for (int c = 0; c < N; ++c) {
      const unsigned above = up[4 * x + c];
      const auto value =
          static_cast<unsigned char>(in[N * x + c] + predictor(left[c], above, upLeft[c]));
      out[4 * x + c] = value;
      left[c] = value;
      upLeft[c] = above;
    }
  if constexpr (N == 3)
    for (std::size_t x = 0; x < width; ++x) out[4 * x + 3] = 255;
}

template <int N>
void unfilterRow(unsigned filter, const unsigned char* in, const unsigned char* up,
                 unsigned char* out, std::size_t width) {
  switch (filter) {
    case 0:
      unfilterRow<N>(in, up, out, width, [](unsigned, unsigned, unsigned) { return 0u; });
      break;
    case 1:  // Sub
      unfilterRow<N>(in, up, out, width, [](unsigned a, unsigned, unsigned) { return a; });
      break;
    case 2:  // Up
      unfilterRow<N>(in, up, out, width, [](unsigned, unsigned b, unsigned) { return b; });
      break;
    case 3:  // Average
      unfilterRow<N>(in, up, out, width,
                     [](unsigned a, unsigned b, unsigned) { return (a + b) >> 1; });
      break;
    default:  // 4, Paeth: whichever of a, b and c is nearest to a + b - c, in that order on ties
      unfilterRow<N>(in, up, out, width, [](unsigned a, unsigned b, unsigned c) {
        const int pa = std::abs(static_cast<int>(b) - static_cast<int>(c));
        const int pb = std::abs(static_cast<int>(a) - static_cast<int>(c));
        const int pc = std::abs(static_cast<int>(a + b) - 2 * static_cast<int>(c));
        return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      });
      break;
  }
}

// Unfilters the rows in place: `raw` (a filter byte and N bytes a pixel per row) lies in the
// same buffer as `rgba` (4 bytes a pixel), ending where the picture ends. Each byte is written
// only after it has been read: the first row's RGBA starts before its input, and an output row
// gains on its input one byte per pixel for RGB, none for RGBA, which the distance at the row's
// start, at least the width, leaves room for. One buffer instead of two: the raw rows of a 2048^2
// texture are 12-16 MiB of memory each decode would fault in afresh.
template <int N>
bool unfilter(const unsigned char* raw, std::size_t width, std::size_t height,
              unsigned char* rgba) {
  const std::size_t inStride = 1 + N * width, outStride = 4 * width;
  const std::vector<unsigned char> zeros(outStride, 0);
  const unsigned char* up = zeros.data();
  for (std::size_t y = 0; y < height; ++y) {
    const unsigned char* in = raw + y * inStride;
    const unsigned filter = in[0];
    if (filter > 4) return false;
    unsigned char* out = rgba + y * outStride;
    unfilterRow<N>(filter, in + 1, up, out, width);
    up = out;
  }
  return true;
}

}  // namespace

DecodedPng decodePngTexture(const unsigned char* bytes, std::size_t size, std::uint32_t maxSide,
                            std::uint64_t maxTexels) {
  DecodedPng out;
  Layout layout;
  if (!parse(bytes, size, layout)) return out;
  const std::uint64_t width = layout.width, height = layout.height;
  if (width == 0 || height == 0 || width > maxSide || height > maxSide ||
      width * height > maxTexels)
    return out;
  const std::uint64_t rawBytes = height * (1 + width * static_cast<std::uint64_t>(layout.channels));
  if (rawBytes > std::numeric_limits<std::size_t>::max() / 2) return out;

  // One zlib stream over the IDAT chunks, which need joining only when there are several.
  std::vector<unsigned char> joined;
  const unsigned char* stream = layout.data.front().first;
  std::size_t streamBytes = layout.data.front().second;
  if (layout.data.size() > 1) {
    std::size_t total = 0;
    for (const auto& [data, length] : layout.data) total += length;  // within the file's size
    joined.reserve(total);
    for (const auto& [data, length] : layout.data) joined.insert(joined.end(), data, data + length);
    stream = joined.data();
    streamBytes = joined.size();
  }
  // A stream too short for the rows is refused before their buffer is made: the loader bounds
  // the rows by the file's size, but a file padded with an ancillary chunk passes that, and a
  // few bytes of data claiming a 16384^2 picture would make this decoder zero a gigabyte.
  if (rawBytes > streamBytes * kMaxDeflateExpansion) return out;
  const std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> inflater(
      libdeflate_alloc_decompressor());
  if (!inflater) return out;
  const auto pictureBytes = static_cast<std::size_t>(width * height * 4);
  const std::size_t bufferBytes = std::max(pictureBytes, static_cast<std::size_t>(rawBytes));
  out.rgba.resize(bufferBytes);
  unsigned char* raw = out.rgba.data() + (bufferBytes - rawBytes);
  // Exactly the rows' bytes, with a good Adler-32; anything else goes to stb.
  if (libdeflate_zlib_decompress(inflater.get(), stream, streamBytes, raw,
                                 static_cast<std::size_t>(rawBytes),
                                 nullptr) != LIBDEFLATE_SUCCESS) {
    out.rgba = {};
    return out;
  }
  joined = {};
  const bool unfiltered = layout.channels == 4 ? unfilter<4>(raw, width, height, out.rgba.data())
                                               : unfilter<3>(raw, width, height, out.rgba.data());
  if (!unfiltered) {
    out.rgba = {};
    return out;
  }
  out.rgba.resize(pictureBytes);
  out.ok = true;
  out.width = static_cast<int>(width);
  out.height = static_cast<int>(height);
  return out;
}

}  // namespace omnishadow::gltf_detail
