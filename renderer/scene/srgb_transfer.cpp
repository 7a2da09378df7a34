#include "renderer/scene/srgb_transfer.h"

#include <immintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
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
  // A bucket is the floats with the same bits above these: 32,512 buckets below 1.0f.
  static constexpr int kBucketShift = 15;

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
    for (std::uint32_t bucket = 0; bucket <= (kOneBits >> kBucketShift); ++bucket)
      start_[bucket] = srgb8Exact(std::bit_cast<float>(bucket << kBucketShift));
  }

  const std::array<float, 256>& steps() const { return steps_; }
  // The byte at the start of each bucket, as bytes with 3 more after the last: an AVX2 gather
  // reads 4 bytes at each bucket's byte.
  const std::uint8_t* starts() const { return start_.data(); }
  // [k]: the first float of byte k + 1 ([255]: +infinity).
  const float* firstOfNext() const { return firstOf_.data() + 1; }

  // NaN and values below 0 give 0, values above 1 give 255, as srgbEncode clamps them.
  std::uint8_t operator()(float linear) const {
    const float c = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;
    const int start = start_[std::bit_cast<std::uint32_t>(c) >> kBucketShift];
    return static_cast<std::uint8_t>(start + (c >= firstOf_[start + 1] ? 1 : 0));
  }

 private:
  static constexpr std::uint32_t kOneBits = 0x3f800000u;  // 1.0f
  std::array<float, 257> firstOf_{};                      // [k]: the first float of byte k
  std::array<std::uint8_t, (kOneBits >> kBucketShift) + 1 + 3> start_{};
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

namespace {

// The CPU's support, asked once.
bool hasAvx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  return avx2;
}

// Zeros in a register of their own at each call. A gather merges into its destination, so it
// waits for whatever last wrote that register; with every lane gathered, GCC sees no use for
// the zeros and gathers into the previous step's result, which chains the steps one after the
// other (the RGBA texels took 2.5x as long in a micro-benchmark). The empty asm hides the zeros'
// value, so each gather gets a freshly zeroed register.
template <typename Vector>
__attribute__((target("avx2"))) Vector freshZeros() {
  Vector zeros{};
  asm volatile("" : "+x"(zeros));
  return zeros;
}

// srgb8() of eight values, as Srgb8Table::operator() computes it: clamped (NaN and values not
// above 0 to 0, values above 1 to 1), the start of the float's bucket, plus one where the value
// is at least the next step.
__attribute__((target("avx2"))) __m256i srgb8Avx2(__m256 linear, const Srgb8Table& table) {
  const __m256 clamped = _mm256_and_ps(_mm256_min_ps(linear, _mm256_set1_ps(1.0f)),
                                       _mm256_cmp_ps(linear, _mm256_setzero_ps(), _CMP_GT_OQ));
  const __m256i bucket = _mm256_srli_epi32(_mm256_castps_si256(clamped), Srgb8Table::kBucketShift);
  const __m256i every = _mm256_set1_epi32(-1);
  const __m256i start = _mm256_and_si256(
      _mm256_mask_i32gather_epi32(freshZeros<__m256i>(),
                                  reinterpret_cast<const int*>(table.starts()), bucket, every, 1),
      _mm256_set1_epi32(0xff));
  const __m256 next = _mm256_mask_i32gather_ps(freshZeros<__m256>(), table.firstOfNext(), start,
                                               _mm256_castsi256_ps(every), 4);
  // The comparison's lanes are all ones (-1) where the byte steps up.
  return _mm256_sub_epi32(start, _mm256_castps_si256(_mm256_cmp_ps(clamped, next, _CMP_GE_OQ)));
}

// Eight 32-bit lanes of values 0..255 as eight bytes, in lane order.
__attribute__((target("avx2"))) std::uint64_t packBytes(__m256i lanes) {
  const __m128i words =
      _mm_packus_epi32(_mm256_castsi256_si128(lanes), _mm256_extracti128_si256(lanes, 1));
  return static_cast<std::uint64_t>(_mm_cvtsi128_si64(_mm_packus_epi16(words, words)));
}

// A float frame or mipmap level is larger than the caches and comes from memory; without the
// prefetch, 1 KiB ahead, the conversion of Sundial's frame waited on its loads (7.4 ms of CPU a
// render against 2.8 with it, in a perf profile of 8 renders).
constexpr std::size_t kPrefetchBytes = 1024;

// Eight RGBA pixels per step: their 24 colour channels moved into three registers, alpha left
// out, so that every gathered lane is a colour. Two pixels a step gathered alpha in a quarter of
// the lanes for nothing: a 1280x720 frame on one thread took 3.6-5.3 ms (median 5.0 of 15
// runs of a /tmp micro-benchmark), this way 2.5-4.5 (median 3.4).
__attribute__((target("avx2"))) std::size_t rgbaToSrgb8RgbAvx2(const float* rgba, std::size_t count,
                                                               float scale, std::uint8_t* rgb) {
  const Srgb8Table& table = srgb8Table();
  const __m256 factor = _mm256_set1_ps(scale);
  // v0..v3 hold pixels 0-1, 2-3, 4-5 and 6-7 as RGBA RGBA; the lanes each gives its register:
  // c0 = pixels 0 and 1 (v0), pixel 2's R and G (v1);
  const __m256i c0From0 = _mm256_setr_epi32(0, 1, 2, 4, 5, 6, 0, 0);
  const __m256i c0From1 = _mm256_setr_epi32(0, 0, 0, 0, 0, 0, 0, 1);
  // c1 = pixel 2's B and pixel 3 (v1), pixel 4 and pixel 5's R (v2);
  const __m256i c1From1 = _mm256_setr_epi32(2, 4, 5, 6, 0, 0, 0, 0);
  const __m256i c1From2 = _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 2, 4);
  // c2 = pixel 5's G and B (v2), pixels 6 and 7 (v3).
  const __m256i c2From2 = _mm256_setr_epi32(5, 6, 0, 0, 0, 0, 0, 0);
  const __m256i c2From3 = _mm256_setr_epi32(0, 0, 0, 1, 2, 4, 5, 6);
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    const float* p = rgba + i * 4;
    _mm_prefetch(reinterpret_cast<const char*>(p) + kPrefetchBytes, _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(p) + kPrefetchBytes + 64, _MM_HINT_T0);
    const __m256 r0 = _mm256_loadu_ps(p), r1 = _mm256_loadu_ps(p + 8);
    const __m256 r2 = _mm256_loadu_ps(p + 16), r3 = _mm256_loadu_ps(p + 24);
    // Eight pixels of zero bits (the background a frame was cleared to) are zero bytes: no
    // gathers. Most of a frame's drawn rectangle can be background (Sundial: 72%).
    const __m256i any =
        _mm256_castps_si256(_mm256_or_ps(_mm256_or_ps(r0, r1), _mm256_or_ps(r2, r3)));
    if (_mm256_testz_si256(any, any)) {
      std::memset(rgb + i * 3, 0, 24);
      continue;
    }
    const __m256 v0 = _mm256_mul_ps(r0, factor);
    const __m256 v1 = _mm256_mul_ps(r1, factor);
    const __m256 v2 = _mm256_mul_ps(r2, factor);
    const __m256 v3 = _mm256_mul_ps(r3, factor);
    const __m256 c0 = _mm256_blend_ps(_mm256_permutevar8x32_ps(v0, c0From0),
                                      _mm256_permutevar8x32_ps(v1, c0From1), 0xC0);
    const __m256 c1 = _mm256_blend_ps(_mm256_permutevar8x32_ps(v1, c1From1),
                                      _mm256_permutevar8x32_ps(v2, c1From2), 0xF0);
    const __m256 c2 = _mm256_blend_ps(_mm256_permutevar8x32_ps(v2, c2From2),
                                      _mm256_permutevar8x32_ps(v3, c2From3), 0xFC);
    const std::uint64_t b0 = packBytes(srgb8Avx2(c0, table));
    const std::uint64_t b1 = packBytes(srgb8Avx2(c1, table));
    const std::uint64_t b2 = packBytes(srgb8Avx2(c2, table));
    std::memcpy(rgb + i * 3, &b0, 8);
    std::memcpy(rgb + i * 3 + 8, &b1, 8);
    std::memcpy(rgb + i * 3 + 16, &b2, 8);
  }
  return i;
}

__attribute__((target("avx2"))) std::size_t rgbaToSrgb8RgbaAvx2(const float* rgba,
                                                                std::size_t count,
                                                                std::uint8_t* out) {
  const Srgb8Table& table = srgb8Table();
  std::size_t i = 0;
  for (; i + 2 <= count; i += 2) {
    _mm_prefetch(reinterpret_cast<const char*>(rgba + i * 4) + kPrefetchBytes, _MM_HINT_T0);
    const __m256 texels = _mm256_loadu_ps(rgba + i * 4);
    const __m256i srgb = srgb8Avx2(texels, table);
    // As linear8(): max with 0 first (NaN gives 0), min with 1, times 255, plus 0.5, truncated.
    const __m256 clamped =
        _mm256_min_ps(_mm256_max_ps(texels, _mm256_setzero_ps()), _mm256_set1_ps(1.0f));
    const __m256i linear = _mm256_cvttps_epi32(
        _mm256_add_ps(_mm256_mul_ps(clamped, _mm256_set1_ps(255.0f)), _mm256_set1_ps(0.5f)));
    const std::uint64_t bytes = packBytes(_mm256_blend_epi32(srgb, linear, 0x88));
    std::memcpy(out + i * 4, &bytes, 8);
  }
  return i;
}

}  // namespace

std::uint8_t linear8(float linear) {
  const float v = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;
  return static_cast<std::uint8_t>(v * 255.0f + 0.5f);
}

void toLinear8(const float* values, std::size_t count, std::uint8_t* out) {
  // SSE2, which every x86-64 CPU has. A linear texture's mipmaps called linear8() once per
  // channel: 13-22 ms of a 2048^2 chain, against 8-12 for an sRGB one. The same operations in
  // the same order, so the same bytes: max with 0 first (NaN gives 0), min with 1, times 255,
  // plus 0.5, truncated.
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 scale = _mm_set1_ps(255.0f), half = _mm_set1_ps(0.5f);
  const auto codes = [&](const float* four) {
    const __m128 v = _mm_min_ps(_mm_max_ps(_mm_loadu_ps(four), zero), one);
    return _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(v, scale), half));
  };
  std::size_t i = 0;
  for (; i + 16 <= count; i += 16) {
    const __m128i low = _mm_packs_epi32(codes(values + i), codes(values + i + 4));
    const __m128i high = _mm_packs_epi32(codes(values + i + 8), codes(values + i + 12));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(low, high));
  }
  for (; i < count; ++i) out[i] = linear8(values[i]);
}

void rgbaToSrgb8Rgb(const float* rgba, std::size_t count, float scale, std::uint8_t* rgb) {
  const std::size_t done = hasAvx2() ? rgbaToSrgb8RgbAvx2(rgba, count, scale, rgb) : 0;
  for (std::size_t c = 0; c < 3; ++c)
    toSrgb8(rgba + done * 4 + c, count - done, 4, scale, rgb + done * 3 + c, 3);
}

void rgbaToSrgb8Rgba(const float* rgba, std::size_t count, std::uint8_t* out) {
  const std::size_t done = hasAvx2() ? rgbaToSrgb8RgbaAvx2(rgba, count, out) : 0;
  for (std::size_t i = done * 4; i < count * 4; ++i)
    out[i] = i % 4 == 3 ? linear8(rgba[i]) : srgb8(rgba[i]);
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
