#pragma once

#include <cstdint>
#include <string>

namespace omnishadow {

// What readImage() takes: files up to 2 GiB, decoded to at most 2^28 channel values (1 GiB of
// floats, e.g. 8192 x 8192 RGBA). The size is checked from the header, before the pixels are
// allocated: a 1 MB PNG may claim 16384 x 16384 (4 GiB as float).
inline constexpr std::uint64_t kMaxImageFileBytes = std::uint64_t{2} << 30;
inline constexpr std::uint64_t kMaxImageValues = std::uint64_t{1} << 28;

// Empty when an image of this size may be decoded, else why not.
inline std::string imageSizeProblem(std::int64_t width, std::int64_t height,
                                    std::int64_t channels) {
  const auto positive = [](std::int64_t v) { return static_cast<std::uint64_t>(v > 0 ? v : 0); };
  // Each factor is below 2^32 in every format read here, so the product cannot overflow.
  if (positive(width) * positive(height) * positive(channels) <= kMaxImageValues) return {};
  return std::to_string(width) + "x" + std::to_string(height) + " with " +
         std::to_string(channels) + " channels is too large (at most " +
         std::to_string(kMaxImageValues) + " channel values, e.g. 8192x8192 RGBA)";
}

}  // namespace omnishadow
