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
#include <vector>

#include "renderer/core/default_init_allocator.h"

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

template <class T>
using Buffer = std::vector<T, DefaultInitAllocator<T>>;

// `bitDepth` 8 or 16; `rowBytes(y, out)` gives row y (top first) as PNG stores its samples
// (16-bit ones big-endian), in `out` or elsewhere, and returns where they are.
template <class RowBytes>
std::string encode(int width, int height, int channels, int bitDepth, RowBytes rowBytesOf,
                   const PngEncoding& encoding) {
  // Filters work on bytes, comparing each with the same byte of the pixel to its left.
  const std::size_t bpp = static_cast<std::size_t>(channels * bitDepth / 8);
  const std::size_t rowBytes = static_cast<std::size_t>(width) * bpp;
  const auto rows = static_cast<std::size_t>(height);
  // Each row: its filter type byte, then the filtered bytes. Every byte is written below, and
  // buffers this size (megabytes) are fresh pages: zeroing them first would fault them twice.
  Buffer<std::uint8_t> filtered(rows * (rowBytes + 1));
  const std::vector<std::uint8_t> zeros(rowBytes, 0);
  std::array<Buffer<std::uint8_t>, 2> rowCopies;  // where a row source needs them
  for (auto& copy : rowCopies) copy.resize(rowBytes);
  std::array<Buffer<std::uint8_t>, 5> candidates;
  if (encoding.filter == kAdaptivePngFilter)
    for (auto& candidate : candidates) candidate.resize(rowBytes);
  const std::uint8_t* previous = zeros.data();
  for (std::size_t y = 0; y < rows; ++y) {
    const std::uint8_t* row = rowBytesOf(y, rowCopies[y % 2].data());
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
      std::copy(candidates[best].begin(), candidates[best].end(), out + 1);
    } else {
      filterRow(best, row, previous, rowBytes, bpp, out + 1);
    }
    out[0] = static_cast<std::uint8_t>(best);
    previous = row;
  }
  const int level = encoding.level > 0 ? encoding.level : kDefaultPngLevel;
  std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor(
      libdeflate_alloc_compressor(level));
  if (!compressor) throw std::bad_alloc();
  Buffer<char> compressed(libdeflate_zlib_compress_bound(compressor.get(), filtered.size()));
  const std::size_t size = libdeflate_zlib_compress(
      compressor.get(), filtered.data(), filtered.size(), compressed.data(), compressed.size());
  static constexpr char kColorType[] = {0, 0, 4, 2, 6};  // by channel count
  std::string header;
  appendBigEndian(header, static_cast<std::uint32_t>(width));
  appendBigEndian(header, static_cast<std::uint32_t>(height));
  // bit depth, colour type, deflate, filters, no interlace
  header += {static_cast<char>(bitDepth), kColorType[channels], 0, 0, 0};
  std::string png("\x89PNG\r\n\x1a\n", 8);
  png.reserve(png.size() + 25 + size + 12 + 12);
  appendChunk(png, "IHDR", header);
  // PNG chunks hold at most 2^31 - 1 bytes; decoders join consecutive IDATs.
  constexpr std::size_t kMaxChunk = std::size_t{1} << 30;
  const std::string_view data(compressed.data(), size);
  for (std::size_t at = 0; at < size; at += kMaxChunk)
    appendChunk(png, "IDAT", data.substr(at, kMaxChunk));
  appendChunk(png, "IEND", {});
  return png;
}

}  // namespace

std::string encodePng(int width, int height, int channels, const std::vector<std::uint8_t>& pixels,
                      const PngEncoding& encoding) {
  const std::size_t rowBytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels);
  return encode(
      width, height, channels, 8,
      [&](std::size_t y, std::uint8_t*) { return pixels.data() + y * rowBytes; }, encoding);
}

std::string encodePng16(int width, int height, const std::vector<std::uint16_t>& pixels,
                        const PngEncoding& encoding) {
  const auto w = static_cast<std::size_t>(width);
  return encode(
      width, height, 1, 16,
      [&](std::size_t y, std::uint8_t* out) {
        const std::uint16_t* row = pixels.data() + y * w;
        for (std::size_t x = 0; x < w; ++x) {
          out[2 * x] = static_cast<std::uint8_t>(row[x] >> 8);
          out[2 * x + 1] = static_cast<std::uint8_t>(row[x] & 0xff);
        }
        return static_cast<const std::uint8_t*>(out);
      },
      encoding);
}

}  // namespace omnishadow
