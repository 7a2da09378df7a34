#include "renderer/output/radiance_hdr_decoder.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "renderer/core/errors.h"
#include "renderer/output/image_limits.h"

namespace omnishadow {
namespace {

// Longer header lines than this are not a Radiance header (the format's own are short).
constexpr std::size_t kMaxHeaderLine = 4096;
constexpr std::size_t kMaxHeaderLines = 1024;

class HdrReader {
 public:
  HdrReader(const std::string& bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(name_ + ": cannot read image: " + why);
  }

  // The next line without its newline; fails at the end of the file or on an overlong line.
  std::string_view line() {
    const std::size_t end = bytes_.find('\n', at_);
    if (end == std::string::npos || end - at_ > kMaxHeaderLine)
      fail("the Radiance HDR header is truncated or malformed");
    const std::string_view text(bytes_.data() + at_, end - at_);
    at_ = end + 1;
    return text;
  }

  std::uint8_t byte() {
    if (at_ >= bytes_.size()) fail("the Radiance HDR pixels are truncated");
    return static_cast<std::uint8_t>(bytes_[at_++]);
  }
  std::size_t position() const { return at_; }
  void seek(std::size_t position) { at_ = position; }
  std::size_t remaining() const { return bytes_.size() - at_; }

 private:
  const std::string& bytes_;
  const std::string& name_;
  std::size_t at_ = 0;
};

float rgbeComponent(std::uint8_t mantissa, std::uint8_t exponent) {
  if (exponent == 0) return 0.0f;
  return std::ldexp(static_cast<float>(mantissa) + 0.5f, static_cast<int>(exponent) - 136);
}

// "-Y 512 +X 1024": the rows' direction, their count and the columns' count.
bool parseResolution(std::string_view text, bool& bottomUp, long& height, long& width) {
  const auto number = [&](std::string_view& rest, long& value) {
    value = 0;
    std::size_t digits = 0;
    while (digits < rest.size() && rest[digits] >= '0' && rest[digits] <= '9' && digits < 9)
      value = value * 10 + (rest[digits++] - '0');
    rest.remove_prefix(digits);
    return digits > 0;
  };
  if (text.starts_with("-Y "))
    bottomUp = false;
  else if (text.starts_with("+Y "))
    bottomUp = true;
  else
    return false;
  text.remove_prefix(3);
  if (!number(text, height) || !text.starts_with(" +X ")) return false;
  text.remove_prefix(4);
  return number(text, width) && text.empty();
}

}  // namespace

bool isRadianceHdr(const std::string& bytes) {
  return bytes.starts_with("#?RADIANCE") || bytes.starts_with("#?RGBE");
}

FloatImage decodeRadianceHdr(const std::string& bytes, const std::string& name) {
  HdrReader reader(bytes, name);
  if (!isRadianceHdr(bytes)) reader.fail("not a Radiance HDR file");
  reader.line();
  std::size_t lines = 0;
  for (std::string_view text = reader.line(); !text.empty(); text = reader.line()) {
    if (++lines > kMaxHeaderLines) reader.fail("the Radiance HDR header is too long");
    if (text.starts_with("FORMAT=") && text != "FORMAT=32-bit_rle_rgbe")
      reader.fail("only RGBE Radiance HDR files are read, not " + std::string(text.substr(7, 40)));
  }
  bool bottomUp = false;
  long height = 0, width = 0;
  if (!parseResolution(reader.line(), bottomUp, height, width) || width < 1 || height < 1)
    reader.fail("the Radiance HDR resolution line is not \"-Y height +X width\"");
  if (const std::string problem = imageSizeProblem(width, height, 3); !problem.empty())
    reader.fail(problem);
  // Run-length encoded, a row takes at least 2 bytes per channel for every 127 pixels (8 for
  // 127 pixels); a claim of more than 64 pixels per byte left cannot be held by the data, and
  // is refused before its pixels are allocated.
  if (static_cast<double>(width) * static_cast<double>(height) >
      static_cast<double>(reader.remaining()) * 64.0)
    reader.fail("the Radiance HDR pixels are truncated");

  FloatImage image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.channels = {"R", "G", "B"};
  image.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  std::vector<std::uint8_t> scanline(static_cast<std::size_t>(width) * 4);
  for (long row = 0; row < height; ++row) {
    const std::size_t start = reader.position();
    const std::uint8_t a = reader.byte(), b = reader.byte(), c = reader.byte(), d = reader.byte();
    const bool runLength = width >= 8 && width < 32768 && a == 2 && b == 2 && (c & 0x80) == 0;
    if (runLength) {
      if (((static_cast<long>(c) << 8) | d) != width)
        reader.fail("a Radiance HDR scanline's length is not the image's width");
      // Each channel in turn, as runs (count above 128: one value count - 128 times) and
      // literals (count values).
      for (std::size_t channel = 0; channel < 4; ++channel) {
        std::size_t x = 0;
        while (x < static_cast<std::size_t>(width)) {
          std::size_t count = reader.byte();
          const bool run = count > 128;
          if (run) count -= 128;
          if (count == 0 || x + count > static_cast<std::size_t>(width))
            reader.fail("a Radiance HDR scanline's runs overflow the row");
          if (run) {
            const std::uint8_t value = reader.byte();
            for (std::size_t i = 0; i < count; ++i) scanline[(x + i) * 4 + channel] = value;
          } else {
            for (std::size_t i = 0; i < count; ++i) scanline[(x + i) * 4 + channel] = reader.byte();
          }
          x += count;
        }
      }
    } else {
      reader.seek(start);
      for (std::uint8_t& value : scanline) value = reader.byte();
    }
    const long y = bottomUp ? height - 1 - row : row;
    float* out = &image.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) * 3];
    for (long x = 0; x < width; ++x) {
      const std::uint8_t* p = &scanline[static_cast<std::size_t>(x) * 4];
      for (int channel = 0; channel < 3; ++channel)
        out[x * 3 + channel] = rgbeComponent(p[channel], p[3]);
    }
  }
  return image;
}

}  // namespace omnishadow
