#include "renderer/scene/srgb_transfer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

namespace omnishadow {

float srgbEncode(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

namespace {

std::uint8_t srgb8Exact(float linear) {
  return static_cast<std::uint8_t>(std::lround(srgbEncode(linear) * 255.0f));
}

// srgb8Exact() without a pow() per channel (which took 15 ms of a 1280x720 PNG): the byte only
// changes at 255 floats, found once by bisection. A table indexed by the float's top bits holds
// the byte at the start of each bucket of 2^15 floats; no bucket holds more than one step, so
// one comparison with the next step gives the byte. Both facts (srgb8Exact is non-decreasing
// over [0, 1], one step per bucket at most) were checked for every float in [0, 1] when this
// was written; tests/srgb_transfer_test.cpp checks a dense sample and every step.
class Srgb8Table {
 public:
  Srgb8Table() {
    for (int k = 1; k < 256; ++k) {
      std::uint32_t low = 0, high = kOneBits;  // srgb8Exact(low) < k <= srgb8Exact(high)
      while (high - low > 1) {
        const std::uint32_t middle = low + (high - low) / 2;
        (srgb8Exact(std::bit_cast<float>(middle)) >= k ? high : low) = middle;
      }
      firstOf_[k] = std::bit_cast<float>(high);
    }
    firstOf_[256] = std::numeric_limits<float>::infinity();
    std::copy(firstOf_.begin() + 1, firstOf_.end(), steps_.begin());
    for (std::uint32_t bucket = 0; bucket < start_.size(); ++bucket)
      start_[bucket] = srgb8Exact(std::bit_cast<float>(bucket << kBucketShift));
  }

  const std::array<float, 256>& steps() const { return steps_; }

  // NaN and values below 0 give 0, values above 1 give 255, as srgbEncode clamps them.
  std::uint8_t operator()(float linear) const {
    const float c = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;
    const int start = start_[std::bit_cast<std::uint32_t>(c) >> kBucketShift];
    return static_cast<std::uint8_t>(start + (c >= firstOf_[start + 1] ? 1 : 0));
  }

 private:
  static constexpr std::uint32_t kOneBits = 0x3f800000u;  // 1.0f
  static constexpr int kBucketShift = 15;                 // 32,512 buckets below 1.0f
  std::array<float, 257> firstOf_{};                      // [k]: the first float of byte k
  std::array<std::uint8_t, (kOneBits >> kBucketShift) + 1> start_{};
  std::array<float, 256> steps_{};  // firstOf_ from byte 1 on
};

const Srgb8Table& srgb8Table() {
  static const Srgb8Table table;
  return table;
}

}  // namespace

std::uint8_t srgb8(float linear) {
  return srgb8Table()(linear);
}

const std::array<float, 256>& srgb8Steps() {
  return srgb8Table().steps();
}

void toSrgb8(const float* linear, std::size_t count, std::size_t stride, float scale,
             std::uint8_t* out, std::size_t outStride) {
  const Srgb8Table& table = srgb8Table();
  for (std::size_t i = 0; i < count; ++i) out[i * outStride] = table(linear[i * stride] * scale);
}

float srgbDecode(std::uint8_t encoded) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const float c = static_cast<float>(i) / 255.0f;
      t[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    }
    return t;
  }();
  return table[encoded];
}

}  // namespace omnishadow
