#include "renderer/scene/image_mipmaps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "renderer/core/default_init_allocator.h"
#include "renderer/core/two_halves.h"
#include "renderer/scene/srgb_transfer.h"

namespace omnishadow {
namespace {

// The texels of the level above that one texel of a level covers along one axis, and the share
// of each (they sum to 1). A side shrinks by 2 (a side of 1 stays), so a texel covers at most
// three and a half texels above it: at most 4 taps.
struct Taps {
  int first = 0;
  int count = 0;
  std::array<float, 4> weight{};
};

std::vector<Taps> tapsFor(int from, int to) {
  std::vector<Taps> taps(static_cast<std::size_t>(to));
  const double scale = static_cast<double>(from) / to;
  for (int x = 0; x < to; ++x) {
    const double begin = x * scale, end = (x + 1) * scale;
    Taps& t = taps[static_cast<std::size_t>(x)];
    t.first = static_cast<int>(std::floor(begin));
    for (int s = t.first; s < from && s < end && t.count < 4; ++s) {
      const double overlap = std::min(end, s + 1.0) - std::max(begin, static_cast<double>(s));
      t.weight[static_cast<std::size_t>(t.count++)] = static_cast<float>(overlap / scale);
    }
  }
  return taps;
}

// A level in linear values, RGBA. Not zeroed when sized: every value is written (a 2048^2
// image makes a 16 MB level 1).
struct LinearLevel {
  int width = 0;
  int height = 0;
  std::vector<float, DefaultInitAllocator<float>> rgba;
};

// The level below `width` x `height` texels that `texel(x, y, channel)` reads, where the sides
// are not both even: each texel the mean of the area it covers above.
template <typename Texel>
LinearLevel downsample(int width, int height, const Texel& texel) {
  LinearLevel out;
  out.width = std::max(1, width / 2);
  out.height = std::max(1, height / 2);
  out.rgba.resize(static_cast<std::size_t>(out.width) * out.height * 4);
  float* o = out.rgba.data();
  const std::vector<Taps> columns = tapsFor(width, out.width);
  const std::vector<Taps> rows = tapsFor(height, out.height);
  for (const Taps& row : rows)
    for (const Taps& column : columns) {
      std::array<float, 4> sum{};
      for (int j = 0; j < row.count; ++j)
        for (int i = 0; i < column.count; ++i) {
          const float w =
              row.weight[static_cast<std::size_t>(j)] * column.weight[static_cast<std::size_t>(i)];
          for (int c = 0; c < 4; ++c)
            sum[static_cast<std::size_t>(c)] += w * texel(column.first + i, row.first + j, c);
        }
      for (float s : sum) *o++ = s;
    }
  return out;
}

// Rows [y0, y1) of the level below `above`, whose sides are even, from `rows`, the linear values
// of `above`'s rows [2 * y0, 2 * y1), into `out`, which has its size already: each texel the
// mean of a 2x2 box, without the general loop's bookkeeping (3x faster).
void downsampleEvenRows(const float* rows, int aboveWidth, LinearLevel& out, int y0, int y1) {
  const std::size_t row = static_cast<std::size_t>(aboveWidth) * 4;
  float* o = out.rgba.data() + static_cast<std::size_t>(y0) * out.width * 4;
  for (int y = y0; y < y1; ++y) {
    const float* top = rows + 2 * static_cast<std::size_t>(y - y0) * row;
    const float* bottom = top + row;
    for (int x = 0; x < out.width; ++x, top += 8, bottom += 8)
      for (int c = 0; c < 4; ++c)
        *o++ = 0.25f * ((top[c] + top[4 + c]) + (bottom[c] + bottom[4 + c]));
  }
}

// The level below `above`.
LinearLevel levelBelow(const LinearLevel& above) {
  if (above.width % 2 == 0 && above.height % 2 == 0) {
    LinearLevel out;
    out.width = above.width / 2;
    out.height = above.height / 2;
    out.rgba.resize(static_cast<std::size_t>(out.width) * out.height * 4);
    downsampleEvenRows(above.rgba.data(), above.width, out, 0, out.height);
    return out;
  }
  const auto width = static_cast<std::size_t>(above.width);
  return downsample(above.width, above.height, [&](int x, int y, int c) {
    return above.rgba[(static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x)) * 4 +
                      static_cast<std::size_t>(c)];
  });
}

// Rows [y0, y1) of level 1 of 8-bit RGBA with even sides, 2x2 boxes of values decoded by the
// tables, to `o`: row y0's first value, then the rest in order (`width` texels a row).
void downsampleEvenBytes(const Image& base, const std::array<float, 256>& rgbDecode,
                         const std::array<float, 256>& alphaDecode, int width, int y0, int y1,
                         float* o) {
  const std::size_t row = static_cast<std::size_t>(base.width) * 4;
  for (int y = y0; y < y1; ++y) {
    const std::uint8_t* top = base.rgba.data() + 2 * static_cast<std::size_t>(y) * row;
    const std::uint8_t* bottom = top + row;
    for (int x = 0; x < width; ++x, top += 8, bottom += 8, o += 4) {
      for (int c = 0; c < 3; ++c)
        o[c] = 0.25f * ((rgbDecode[top[c]] + rgbDecode[top[4 + c]]) +
                        (rgbDecode[bottom[c]] + rgbDecode[bottom[4 + c]]));
      o[3] = 0.25f * ((alphaDecode[top[3]] + alphaDecode[top[7]]) +
                      (alphaDecode[bottom[3]] + alphaDecode[bottom[7]]));
    }
  }
}

// `texels` RGBA texels of linear values as 8-bit codes.
void roundTexels(const float* from, std::size_t texels, bool srgb, std::uint8_t* to) {
  if (srgb) {
    rgbaToSrgb8Rgba(from, texels, to);
    return;
  }
  toLinear8(from, texels * 4, to);
}

// Rows [y0, y1) of `level` as 8-bit codes into `image`, which has its size already.
void roundRows(const LinearLevel& level, bool srgb, Image& image, int y0, int y1) {
  const std::size_t first = static_cast<std::size_t>(y0) * level.width;
  roundTexels(level.rgba.data() + first * 4, static_cast<std::size_t>(y1 - y0) * level.width, srgb,
              image.rgba.data() + first * 4);
}

Image sized(const std::string& name, int width, int height) {
  Image image;
  image.name = name;
  image.width = width;
  image.height = height;
  image.rgba.resize(static_cast<std::size_t>(width) * height * 4);
  return image;
}

Image rounded(const LinearLevel& level, bool srgb, const std::string& name) {
  Image image = sized(name, level.width, level.height);
  roundRows(level, srgb, image, 0, level.height);
  return image;
}

// From this many texels of the image on, its level 1 (three quarters of the chain's work) is
// made on two threads, half the rows each: Sundial's 2048^2 texture took 16 ms of a single
// render's upload on one. The rows come out the same whichever thread makes them.
constexpr std::size_t kTwoThreadTexels = std::size_t{512} * 512;

// Level 1's rows are made this many at a time, so that their rounding (and level 2, made from
// them) reads them from the cache.
constexpr int kRowsAtATime = 8;

// Levels 1 and 2 of 8-bit RGBA whose sides and level 1's sides are even: their codes go to
// `chain`; level 2's linear values are returned. Level 1's linear values are held a band of rows
// at a time, never whole. Whole, a 2048^2 image's were 16 MB of fresh memory, and once freed they
// left a hole in the heap too small for the frame's textures, which went above it, into pages
// the memory warm-up (cli/memory_warmup.h) reached later (docs/performance.md).
LinearLevel firstTwoLevelsEven(const Image& base, const std::array<float, 256>& rgbDecode,
                               const std::array<float, 256>& alphaDecode, bool srgb,
                               std::vector<Image>& chain) {
  const int oneWidth = base.width / 2, oneHeight = base.height / 2;
  LinearLevel two;
  two.width = oneWidth / 2;
  two.height = oneHeight / 2;
  two.rgba.resize(static_cast<std::size_t>(two.width) * two.height * 4);
  Image oneCodes = sized(base.name, oneWidth, oneHeight);
  Image twoCodes = sized(base.name, two.width, two.height);
  // In pairs of level 1's rows, one row of level 2 each, so that no pair straddles the halves.
  const auto pairs = [&](std::size_t first, std::size_t end) {
    std::vector<float, DefaultInitAllocator<float>> band(static_cast<std::size_t>(oneWidth) *
                                                         kRowsAtATime * 4);
    for (std::size_t from = first; from < end; from += kRowsAtATime / 2) {
      const auto y0 = static_cast<int>(from);
      const auto y1 = static_cast<int>(std::min(end, from + kRowsAtATime / 2));
      const int rows = 2 * (y1 - y0);
      // The band holds level 1's rows [2 * y0, 2 * y1), made and rounded as firstLevelEven()
      // makes and rounds them.
      downsampleEvenBytes(base, rgbDecode, alphaDecode, oneWidth, 2 * y0, 2 * y1, band.data());
      const std::size_t firstTexel = 2 * static_cast<std::size_t>(y0) * oneWidth;
      roundTexels(band.data(), static_cast<std::size_t>(rows) * oneWidth, srgb,
                  oneCodes.rgba.data() + firstTexel * 4);
      downsampleEvenRows(band.data(), oneWidth, two, y0, y1);
      roundRows(two, srgb, twoCodes, y0, y1);
    }
  };
  inTwoHalves(static_cast<std::size_t>(two.height),
              static_cast<std::size_t>(base.width) * base.height >= kTwoThreadTexels, pairs);
  chain.push_back(std::move(oneCodes));
  chain.push_back(std::move(twoCodes));
  return two;
}

// Level 1 of 8-bit RGBA with even sides: its linear values, and its codes into `codes`.
LinearLevel firstLevelEven(const Image& base, const std::array<float, 256>& rgbDecode,
                           const std::array<float, 256>& alphaDecode, bool srgb, Image& codes) {
  LinearLevel level;
  level.width = base.width / 2;
  level.height = base.height / 2;
  level.rgba.resize(static_cast<std::size_t>(level.width) * level.height * 4);
  codes = sized(base.name, level.width, level.height);
  const auto rows = [&](std::size_t first, std::size_t end) {
    for (std::size_t from = first; from < end; from += kRowsAtATime) {
      const auto y0 = static_cast<int>(from);
      const auto y1 = static_cast<int>(std::min(end, from + kRowsAtATime));
      downsampleEvenBytes(base, rgbDecode, alphaDecode, level.width, y0, y1,
                          level.rgba.data() + static_cast<std::size_t>(y0) * level.width * 4);
      roundRows(level, srgb, codes, y0, y1);
    }
  };
  inTwoHalves(static_cast<std::size_t>(level.height),
              static_cast<std::size_t>(base.width) * base.height >= kTwoThreadTexels, rows);
  return level;
}

}  // namespace

std::vector<Image> mipmapChain(const Image& base, bool srgb) {
  std::vector<Image> chain;
  if (base.width <= 1 && base.height <= 1) return chain;
  std::array<std::array<float, 256>, 2> decode{};  // [0]: RGB, [1]: alpha (and linear RGB)
  for (int v = 0; v < 256; ++v) {
    decode[1][static_cast<std::size_t>(v)] = static_cast<float>(v) / 255.0f;
    decode[0][static_cast<std::size_t>(v)] =
        srgb ? srgbDecode(static_cast<std::uint8_t>(v)) : decode[1][static_cast<std::size_t>(v)];
  }
  LinearLevel level;
  if (base.width % 4 == 0 && base.height % 4 == 0) {
    level = firstTwoLevelsEven(base, decode[0], decode[1], srgb, chain);
  } else if (base.width % 2 == 0 && base.height % 2 == 0) {
    Image codes;
    level = firstLevelEven(base, decode[0], decode[1], srgb, codes);
    chain.push_back(std::move(codes));
  } else {
    const auto baseWidth = static_cast<std::size_t>(base.width);
    level = downsample(base.width, base.height, [&](int x, int y, int c) {
      const std::uint8_t code =
          base.rgba[(static_cast<std::size_t>(y) * baseWidth + static_cast<std::size_t>(x)) * 4 +
                    static_cast<std::size_t>(c)];
      return decode[c == 3 ? 1 : 0][code];
    });
    chain.push_back(rounded(level, srgb, base.name));
  }
  while (level.width > 1 || level.height > 1) {
    level = levelBelow(level);
    chain.push_back(rounded(level, srgb, base.name));
  }
  return chain;
}

}  // namespace omnishadow
