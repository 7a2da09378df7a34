#include "renderer/output/png_encoder.h"

#include <libdeflate.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <string_view>

namespace omnishadow {
namespace {

void appendBigEndian(std::string& out, std::uint32_t value) {
  out.push_back(static_cast<char>(value >> 24));
  out.push_back(static_cast<char>(value >> 16));
  out.push_back(static_cast<char>(value >> 8));
  out.push_back(static_cast<char>(value));
}

// length, type, data, CRC of type and data.
void appendChunk(std::string& out, std::string_view type, std::string_view data) {
  appendBigEndian(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t typeAt = out.size();
  out.append(type);
  out.append(data);
  const std::uint32_t crc = libdeflate_crc32(0, out.data() + typeAt, type.size() + data.size());
  appendBigEndian(out, crc);
}

int paethPredictor(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  return pb <= pc ? b : c;
}

// Row `row` filtered with PNG filter `type` (0 None .. 4 Paeth) into `out` (rowBytes long);
// `previous` is the row above (PNG treats the one above the first row as zeros). One loop per
// type, so that the compiler vectorizes the simple ones.
void filterRow(int type, const std::uint8_t* row, const std::uint8_t* previous,
               std::size_t rowBytes, std::size_t bpp, std::uint8_t* out) {
  auto left = [&](std::size_t i) { return i >= bpp ? row[i - bpp] : 0; };
  auto upLeft = [&](std::size_t i) { return i >= bpp ? previous[i - bpp] : 0; };
  switch (type) {
    case 0:
      std::copy(row, row + rowBytes, out);
      break;
    case 1:
      for (std::size_t i = 0; i < rowBytes; ++i)
        out[i] = static_cast<std::uint8_t>(row[i] - left(i));
      break;
    case 2:
      for (std::size_t i = 0; i < rowBytes; ++i)
        out[i] = static_cast<std::uint8_t>(row[i] - previous[i]);
      break;
    case 3:
      for (std::size_t i = 0; i < rowBytes; ++i)
        out[i] = static_cast<std::uint8_t>(row[i] - (left(i) + previous[i]) / 2);
      break;
    default:
      for (std::size_t i = 0; i < rowBytes; ++i)
        out[i] =
            static_cast<std::uint8_t>(row[i] - paethPredictor(left(i), previous[i], upLeft(i)));
      break;
  }
}

// Sum of the filtered bytes taken as signed values: small sums compress well.
std::size_t cost(const std::uint8_t* bytes, std::size_t count) {
  std::size_t sum = 0;
  for (std::size_t i = 0; i < count; ++i)
    sum += static_cast<std::size_t>(std::abs(static_cast<std::int8_t>(bytes[i])));
  return sum;
}

struct CompressorDeleter {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

// `bitDepth` 8 or 16; `bytes` hold the samples as PNG stores them (16-bit ones big-endian).
std::string encode(int width, int height, int channels, int bitDepth, const std::uint8_t* bytes,
                   const PngEncoding& encoding) {
  // Filters work on bytes, comparing each with the same byte of the pixel to its left.
  const std::size_t bpp = static_cast<std::size_t>(channels * bitDepth / 8);
  const std::size_t rowBytes = static_cast<std::size_t>(width) * bpp;
  const auto rows = static_cast<std::size_t>(height);

  // Each row: its filter type byte, then the filtered bytes.
  std::vector<std::uint8_t> filtered(rows * (rowBytes + 1));
  const std::vector<std::uint8_t> zeros(rowBytes, 0);
  std::array<std::vector<std::uint8_t>, 5> candidates;
  for (auto& candidate : candidates) candidate.resize(rowBytes);
  for (std::size_t y = 0; y < rows; ++y) {
    const std::uint8_t* row = bytes + y * rowBytes;
    const std::uint8_t* previous = y > 0 ? row - rowBytes : zeros.data();
    std::uint8_t* out = filtered.data() + y * (rowBytes + 1);
    int best = encoding.filter;
    if (encoding.filter == kAdaptivePngFilter) {
      std::size_t bestCost = SIZE_MAX;
      for (int type = 0; type < 5; ++type) {
        filterRow(type, row, previous, rowBytes, bpp, candidates[type].data());
        const std::size_t c = cost(candidates[type].data(), rowBytes);
        if (c < bestCost) {
          bestCost = c;
          best = type;
        }
      }
    } else {
      filterRow(best, row, previous, rowBytes, bpp, candidates[best].data());
    }
    out[0] = static_cast<std::uint8_t>(best);
    std::copy(candidates[best].begin(), candidates[best].end(), out + 1);
  }

  const int level = encoding.level > 0 ? encoding.level : kDefaultPngLevel;
  std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor(
      libdeflate_alloc_compressor(level));
  if (!compressor) throw std::bad_alloc();
  std::string compressed(libdeflate_zlib_compress_bound(compressor.get(), filtered.size()), '\0');
  const std::size_t size = libdeflate_zlib_compress(
      compressor.get(), filtered.data(), filtered.size(), compressed.data(), compressed.size());
  compressed.resize(size);

  static constexpr char kColorType[] = {0, 0, 4, 2, 6};  // by channel count
  std::string header;
  appendBigEndian(header, static_cast<std::uint32_t>(width));
  appendBigEndian(header, static_cast<std::uint32_t>(height));
  // bit depth, colour type, deflate, filters, no interlace
  header += {static_cast<char>(bitDepth), kColorType[channels], 0, 0, 0};

  std::string png("\x89PNG\r\n\x1a\n", 8);
  png.reserve(png.size() + 25 + compressed.size() + 12 + 12);
  appendChunk(png, "IHDR", header);
  // PNG chunks hold at most 2^31 - 1 bytes; decoders join consecutive IDATs.
  constexpr std::size_t kMaxChunk = std::size_t{1} << 30;
  for (std::size_t at = 0; at < compressed.size(); at += kMaxChunk)
    appendChunk(png, "IDAT", std::string_view(compressed).substr(at, kMaxChunk));
  appendChunk(png, "IEND", {});
  return png;
}

}  // namespace

std::string encodePng(int width, int height, int channels, const std::vector<std::uint8_t>& pixels,
                      const PngEncoding& encoding) {
  return encode(width, height, channels, 8, pixels.data(), encoding);
}

std::string encodePng16(int width, int height, const std::vector<std::uint16_t>& pixels,
                        const PngEncoding& encoding) {
  std::vector<std::uint8_t> bigEndian(pixels.size() * 2);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    bigEndian[2 * i] = static_cast<std::uint8_t>(pixels[i] >> 8);
    bigEndian[2 * i + 1] = static_cast<std::uint8_t>(pixels[i] & 0xff);
  }
  return encode(width, height, 1, 16, bigEndian.data(), encoding);
}

}  // namespace omnishadow
