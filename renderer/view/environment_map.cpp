#include "renderer/view/environment_map.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <utility>

namespace omnishadow {
namespace {

constexpr double kEnvironmentPi = std::numbers::pi;
constexpr float kEnvironmentPiF = std::numbers::pi_v<float>;

// GGX directions per texel of prefiltered level 1 (roughness 0.2 of 6 levels). Each level down
// has a quarter of the texels, so four times as many directions cost the same, up to what a
// lobe as wide as roughness 1's needs. Against the GGX-weighted mean over every texel of a
// smooth 512 x 256 environment, levels 1 to 5 came out within 1.8, 0.6, 0.2, 0.1 and 0.1
// percent on average (9, 3, 1, 0.3 and 0.4 at the worst texel); 64 directions at every level
// left 2 to 5 percent on average.
constexpr int kFirstLevelSamples = 64;
constexpr int kMaxLevelSamples = 4096;
// Filtered importance sampling reads each sample from the mip whose texels subtend the
// sample's solid angle 1 / (count pdf), plus this many levels. Krivanek and Colbert add 1
// (texels four times larger) against aliasing with random samples. With Hammersley's evenly
// spread ones, 0 left a third of the error of 1 at the same count on smooth and on blocky
// environments, and about the same on per-texel noise and on a small sun: the extra blur of 1
// was the larger error. 1 needs four times the samples for the same error.
constexpr double kSampleLodBias = 0.0;
constexpr int kBrdfTableSamples = 1024;
// The irradiance is summed over every texel of a copy of level 0 this size: small enough for a
// direct sum, large enough (2.8 degree texels) that the cosine is nearly constant over each.
constexpr int kIrradianceSourceWidth = 128;
// At alpha 0 (a mirror) the half vector's formula is 0 / 0 where the radical inverse nears 1;
// this close to 0 the table's smoothest rows are a mirror's anyway.
constexpr double kMinBrdfAlpha = 1e-4;

// Throws std::invalid_argument, naming `caller`, unless `image` has texels and as many values.
void requireEquirect(const EquirectImage& image, const char* caller) {
  if (image.width <= 0 || image.height <= 0)
    throw std::invalid_argument(std::string(caller) + ": empty image (" +
                                std::to_string(image.width) + " x " + std::to_string(image.height) +
                                ")");
  if (image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw std::invalid_argument(std::string(caller) + ": " + std::to_string(image.rgb.size()) +
                                " values for " + std::to_string(image.width) + " x " +
                                std::to_string(image.height) + " RGB texels");
}

// The solid angle of a texel in row y of a width x height grid.
double equirectTexelSolidAngle(int y, int width, int height) {
  const double rowAngle = kEnvironmentPi / height;
  return 2.0 * kEnvironmentPi / width * (std::cos(y * rowAngle) - std::cos((y + 1) * rowAngle));
}

// The direction of the centre of texel (x, y) of a width x height grid.
glm::dvec3 equirectTexelDirection(int x, int y, int width, int height) {
  return glm::dvec3(
      equirectDirection({(static_cast<float>(x) + 0.5f) / static_cast<float>(width),
                         (static_cast<float>(y) + 0.5f) / static_cast<float>(height)}));
}

// Rec. 709 luminance.
double luminanceOf(const glm::dvec3& rgb) {
  return 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b;
}

// Calls rowWork(row) for every row in [0, rows), on up to `threads` threads that take rows in
// turn. Each row's result depends only on its index, so any split gives the same bytes. The
// first exception a row throws (out of memory) is rethrown here, once every thread is done.
template <typename RowWork>
void forEachEnvironmentRow(int rows, int threads, const RowWork& rowWork) {
  const int workers = std::clamp(threads, 1, std::max(rows, 1));
  std::atomic<int> nextRow{0};
  std::mutex failureMutex;
  std::exception_ptr failure;
  const auto work = [&] {
    try {
      for (int row = nextRow.fetch_add(1, std::memory_order_relaxed); row < rows;
           row = nextRow.fetch_add(1, std::memory_order_relaxed))
        rowWork(row);
    } catch (...) {
      nextRow.store(rows, std::memory_order_relaxed);  // the others stop after their row
      const std::lock_guard<std::mutex> lock(failureMutex);
      if (!failure) failure = std::current_exception();
    }
  };
  std::vector<std::thread> helpers;
  helpers.reserve(static_cast<std::size_t>(workers - 1));
  for (int i = 1; i < workers; ++i) {
    // A system out of threads only makes this slower: the calling thread takes the rest.
    try {
      helpers.emplace_back(work);
    } catch (const std::system_error&) {
      break;
    }
  }
  work();
  for (std::thread& helper : helpers) helper.join();
  if (failure) std::rethrow_exception(failure);
}

EquirectImage blankEquirectImage(int width, int height) {
  return {width, height, std::vector<float>(static_cast<std::size_t>(width) * height * 3, 0.0f)};
}

struct AreaTap {
  int index;
  double weight;
};

// For each of `outputCells` cells spanning the same range as `inputCells`, the input cells it
// overlaps, weighted by measure(a, b) of the overlap [a, b] (in input cell units), normalized.
template <typename Measure>
std::vector<std::vector<AreaTap>> areaTaps(int inputCells, int outputCells,
                                           const Measure& measure) {
  std::vector<std::vector<AreaTap>> taps(static_cast<std::size_t>(outputCells));
  const double scale = static_cast<double>(inputCells) / outputCells;
  for (int o = 0; o < outputCells; ++o) {
    const double low = o * scale, high = (o + 1) * scale;
    double total = 0.0;
    for (int i = static_cast<int>(std::floor(low)); i < inputCells && i < high; ++i) {
      const double weight = measure(std::max(low, static_cast<double>(i)),
                                    std::min(high, static_cast<double>(i + 1)));
      if (weight <= 0.0) continue;
      taps[o].push_back({i, weight});
      total += weight;
    }
    for (AreaTap& tap : taps[o]) tap.weight /= total;
  }
  return taps;
}

// equirectCoordinates of a direction known to be of unit length (up to rounding).
glm::vec2 unitEquirectCoordinates(const glm::vec3& d) {
  return {0.5f + std::atan2(d.x, -d.z) / (2.0f * kEnvironmentPiF),
          std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kEnvironmentPiF};
}

// The van der Corput radical inverse in base 2: the bits of i mirrored behind the binary point.
double radicalInverse(std::uint32_t bits) {
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return static_cast<double>(bits) * 0x1p-32;
}

// The half vector about +Z for Hammersley point i of count, (i / count, radicalInverse(i)),
// distributed as D(h) (n.h): the azimuth from the first coordinate, the polar angle from the
// second by the inverse of the GGX distribution's cumulative one.
glm::dvec3 ggxHalfVector(int i, int count, double alpha) {
  const double phi = 2.0 * kEnvironmentPi * i / count;
  const double xi = radicalInverse(static_cast<std::uint32_t>(i));
  const double a2 = alpha * alpha;
  const double cosTheta = std::sqrt((1.0 - xi) / (1.0 + (a2 - 1.0) * xi));
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

double ggxDistribution(double nDotH, double alpha) {
  const double a2 = alpha * alpha;
  const double d = nDotH * nDotH * (a2 - 1.0) + 1.0;
  return a2 / (kEnvironmentPi * d * d);
}

struct LobeSample {
  glm::vec3 direction;  // about +Z, which stands for N = V = R
  float weight;         // n.l
  // The mip to read it from (unclamped) where a level-0 texel subtends most, at the equator.
  float equatorLod;
};

// The GGX lobe's samples that reflect above the surface, and the mip each one is read from.
std::vector<LobeSample> ggxLobe(double alpha, int sampleCount, int level0Width, int level0Height) {
  const double equatorTexelSolidAngle =
      2.0 * kEnvironmentPi * kEnvironmentPi / (static_cast<double>(level0Width) * level0Height);
  std::vector<LobeSample> lobe;
  for (int i = 0; i < sampleCount; ++i) {
    const glm::dvec3 h = ggxHalfVector(i, sampleCount, alpha);
    const glm::dvec3 l = 2.0 * h.z * h - glm::dvec3(0.0, 0.0, 1.0);  // reflect(-V, h)
    if (l.z <= 0.0) continue;
    // pdf(l) = D(h) (n.h) / (4 v.h), which is D(h) / 4 with n = v.
    const double sampleSolidAngle = 4.0 / (sampleCount * ggxDistribution(h.z, alpha));
    const double lod = 0.5 * std::log2(sampleSolidAngle / equatorTexelSolidAngle) + kSampleLodBias;
    lobe.push_back({glm::vec3(l), static_cast<float>(l.z), static_cast<float>(lod)});
  }
  return lobe;
}

// Four floats, added and multiplied element by element (GCC's and Clang's vector extension):
// a bilinear read blends RGB and a padding float in one instruction each.
using Float4 = float __attribute__((vector_size(16)));

Float4 loadFloat4(const float* values) {
  Float4 vector;
  std::memcpy(&vector, values, sizeof vector);
  return vector;
}

// A mip laid out for reading along its rows: RGB padded to four floats, and each row twice
// over plus its first texel again, so that a bilinear read at any column in [0, 2 width) finds
// both its texels without wrapping around.
struct UnrolledMip {
  int width, height;
  std::size_t rowFloats;
  std::vector<float> texels;
};

UnrolledMip unrolledMip(const EquirectImage& image) {
  const std::size_t rowTexels = static_cast<std::size_t>(image.width) * 2 + 1;
  UnrolledMip mip{image.width, image.height, rowTexels * 4,
                  std::vector<float>(rowTexels * 4 * image.height, 0.0f)};
  for (int y = 0; y < image.height; ++y) {
    const float* in = &image.rgb[static_cast<std::size_t>(y) * image.width * 3];
    float* out = &mip.texels[y * mip.rowFloats];
    for (std::size_t x = 0; x < rowTexels; ++x)
      std::memcpy(out + x * 4, in + (x % image.width) * 3, 3 * sizeof(float));
  }
  return mip;
}

// One bilinear read per texel of an output row from one mip, at u shifted by the texel's column.
struct MipRowRead {
  const float* upperRow;
  const float* lowerRow;
  float lowerWeight;  // between the two rows
  float weight;       // of the read in the texel's sum
  float firstColumn;  // where the output row's first texel reads, in [0, width) texels
  float columnStep;   // and how much farther each next texel reads
};

// Level `level` of the specular chain, at perceptual roughness `roughness`: each texel the
// GGX-weighted mean of the radiance around its direction R, by filtered importance sampling of
// `mips`, level 0 and its mips.
EquirectImage prefilterSpecularLevel(const std::vector<UnrolledMip>& mips, int level,
                                     float roughness, int threads) {
  const UnrolledMip& level0 = mips.front();
  const int width = std::max(1, level0.width >> level),
            height = std::max(1, level0.height >> level);
  const int sampleCount =
      std::min(kFirstLevelSamples << (2 * std::min(level - 1, 8)), kMaxLevelSamples);
  const std::vector<LobeSample> lobe =
      ggxLobe(static_cast<double>(roughness) * roughness, sampleCount, level0.width, level0.height);
  // Texel solid angles shrink with sin(theta) toward the poles, where the first row's centre
  // is the smallest there is.
  const float minSinTheta = std::sin(0.5f * kEnvironmentPiF / static_cast<float>(level0.height));
  const int lastMip = static_cast<int>(mips.size()) - 1;

  EquirectImage result = blankEquirectImage(width, height);
  forEachEnvironmentRow(height, threads, [&](int y) {
    // Every texel of the row is its first one turned about +Y by whole columns, and its lobe
    // with it when the lobe's frame follows the turn (the directions of growing theta and phi):
    // a sample then lands at the same v, from the same mip, in every texel, its u shifted by
    // the column. The row's sines, cosines and mips are worked out once, for the first texel.
    const float theta =
        (static_cast<float>(y) + 0.5f) * kEnvironmentPiF / static_cast<float>(height);
    const float phi = (0.5f / static_cast<float>(width) - 0.5f) * 2.0f * kEnvironmentPiF;
    const float sinTheta = std::sin(theta), cosTheta = std::cos(theta);
    const float sinPhi = std::sin(phi), cosPhi = std::cos(phi);
    const glm::vec3 reflected(sinTheta * sinPhi, cosTheta, -sinTheta * cosPhi);
    const glm::vec3 alongTheta(cosTheta * sinPhi, -sinTheta, -cosTheta * cosPhi);
    const glm::vec3 alongPhi(cosPhi, 0.0f, sinPhi);

    std::vector<MipRowRead> reads;
    reads.reserve(lobe.size() * 2);
    float weightSum = 0.0f;
    const auto addRead = [&](int mipIndex, const glm::vec2& uv, float weight) {
      const UnrolledMip& mip = mips[mipIndex];
      const float row = uv.y * static_cast<float>(mip.height) - 0.5f;
      const float rowFloor = std::floor(row);
      const int upper = std::clamp(static_cast<int>(rowFloor), 0, mip.height - 1);
      const int lower = std::clamp(static_cast<int>(rowFloor) + 1, 0, mip.height - 1);
      // u is in [0, 1]: the column in [-0.5, width - 0.5], turned once to [0, width].
      float firstColumn = uv.x * static_cast<float>(mip.width) - 0.5f;
      if (firstColumn < 0.0f) firstColumn += static_cast<float>(mip.width);
      reads.push_back({&mip.texels[upper * mip.rowFloats], &mip.texels[lower * mip.rowFloats],
                       row - rowFloor, weight, firstColumn,
                       static_cast<float>(mip.width) / static_cast<float>(width)});
      weightSum += weight;
    };
    for (const LobeSample& sample : lobe) {
      const glm::vec3 l = sample.direction.x * alongPhi + sample.direction.y * alongTheta +
                          sample.direction.z * reflected;
      const glm::vec2 uv = unitEquirectCoordinates(l);
      const float sinLatitude = std::max(std::sqrt(std::max(0.0f, 1.0f - l.y * l.y)), minSinTheta);
      const float lod = std::clamp(sample.equatorLod - 0.5f * std::log2(sinLatitude), 0.0f,
                                   static_cast<float>(lastMip));
      const int mip = static_cast<int>(lod);
      const float finer = static_cast<float>(mip + 1) - lod;
      addRead(mip, uv, sample.weight * finer);
      if (finer < 1.0f) addRead(mip + 1, uv, sample.weight * (1.0f - finer));
    }

    std::vector<Float4> sums(static_cast<std::size_t>(width), Float4{0.0f, 0.0f, 0.0f, 0.0f});
    for (const MipRowRead& read : reads) {
      for (int x = 0; x < width; ++x) {
        // Below 2 width: the first column is below width, and width steps span width.
        const float column = read.firstColumn + static_cast<float>(x) * read.columnStep;
        const int left = static_cast<int>(column);
        const float right = column - static_cast<float>(left);
        const Float4 upperLeft = loadFloat4(read.upperRow + left * 4);
        const Float4 upperRight = loadFloat4(read.upperRow + left * 4 + 4);
        const Float4 lowerLeft = loadFloat4(read.lowerRow + left * 4);
        const Float4 lowerRight = loadFloat4(read.lowerRow + left * 4 + 4);
        const Float4 upper = upperLeft + (upperRight - upperLeft) * right;
        const Float4 lower = lowerLeft + (lowerRight - lowerLeft) * right;
        sums[x] += read.weight * (upper + (lower - upper) * read.lowerWeight);
      }
    }
    const float normalization = 1.0f / weightSum;
    float* out = &result.rgb[static_cast<std::size_t>(y) * width * 3];
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) out[x * 3 + c] = sums[x][c] * normalization;
  });
  return result;
}

// E(n) / pi at every texel centre of a kIrradianceWidth-wide image: the cosine-weighted mean of
// the radiance over the texels of a small area-averaged copy of level 0, each by its solid
// angle. Dividing by the sum of the weights rather than by pi makes a constant environment
// come out exactly, whatever the error of the sum.
EquirectImage irradianceOf(const EquirectImage& level0, int threads) {
  const EquirectImage source =
      resampleEquirect(level0, kIrradianceSourceWidth, kIrradianceSourceWidth / 2, threads);
  struct SourceTexel {
    glm::dvec3 direction;
    glm::dvec3 radiance;
    double solidAngle;
  };
  std::vector<SourceTexel> texels;
  texels.reserve(static_cast<std::size_t>(source.width) * source.height);
  for (int y = 0; y < source.height; ++y) {
    const double solidAngle = equirectTexelSolidAngle(y, source.width, source.height);
    for (int x = 0; x < source.width; ++x) {
      const float* rgb = &source.rgb[(static_cast<std::size_t>(y) * source.width + x) * 3];
      texels.push_back({equirectTexelDirection(x, y, source.width, source.height),
                        glm::dvec3(rgb[0], rgb[1], rgb[2]), solidAngle});
    }
  }

  EquirectImage result = blankEquirectImage(kIrradianceWidth, kIrradianceWidth / 2);
  forEachEnvironmentRow(result.height, threads, [&](int y) {
    for (int x = 0; x < result.width; ++x) {
      const glm::dvec3 normal = equirectTexelDirection(x, y, result.width, result.height);
      glm::dvec3 sum(0.0);
      double weightSum = 0.0;
      for (const SourceTexel& texel : texels) {
        const double cosine = glm::dot(normal, texel.direction);
        if (cosine <= 0.0) continue;
        sum += cosine * texel.solidAngle * texel.radiance;
        weightSum += cosine * texel.solidAngle;
      }
      const glm::vec3 mean(sum / weightSum);
      float* out = &result.rgb[(static_cast<std::size_t>(y) * result.width + x) * 3];
      out[0] = mean.r;
      out[1] = mean.g;
      out[2] = mean.b;
    }
  });
  return result;
}

// The height-correlated Smith visibility G / (4 n.l n.v) (Heitz 2014).
double smithGgxCorrelatedVisibility(double nDotL, double nDotV, double alpha) {
  const double a2 = alpha * alpha;
  return 0.5 / (nDotL * std::sqrt(nDotV * nDotV * (1.0 - a2) + a2) +
                nDotV * std::sqrt(nDotL * nDotL * (1.0 - a2) + a2));
}

}  // namespace

// Along a row every column subtends the same angle, and down a column a row between polar
// angles a and b subtends (cos a - cos b) of it.
EquirectImage resampleEquirect(const EquirectImage& source, int width, int height, int threads) {
  const std::vector<std::vector<AreaTap>> columnTaps =
      areaTaps(source.width, width, [](double a, double b) { return b - a; });
  const double rowAngle = kEnvironmentPi / source.height;
  const std::vector<std::vector<AreaTap>> rowTaps = areaTaps(
      source.height, height,
      [rowAngle](double a, double b) { return std::cos(a * rowAngle) - std::cos(b * rowAngle); });

  EquirectImage across = blankEquirectImage(width, source.height);
  forEachEnvironmentRow(source.height, threads, [&](int y) {
    const float* in = &source.rgb[static_cast<std::size_t>(y) * source.width * 3];
    float* out = &across.rgb[static_cast<std::size_t>(y) * width * 3];
    for (int x = 0; x < width; ++x) {
      double sum[3] = {0.0, 0.0, 0.0};
      for (const AreaTap& tap : columnTaps[x])
        for (int c = 0; c < 3; ++c) sum[c] += tap.weight * in[tap.index * 3 + c];
      for (int c = 0; c < 3; ++c) out[x * 3 + c] = static_cast<float>(sum[c]);
    }
  });

  EquirectImage result = blankEquirectImage(width, height);
  forEachEnvironmentRow(height, threads, [&](int y) {
    std::vector<double> sum(static_cast<std::size_t>(width) * 3, 0.0);
    for (const AreaTap& tap : rowTaps[y]) {
      const float* in = &across.rgb[static_cast<std::size_t>(tap.index) * width * 3];
      for (int i = 0; i < width * 3; ++i) sum[i] += tap.weight * in[i];
    }
    float* out = &result.rgb[static_cast<std::size_t>(y) * width * 3];
    for (int i = 0; i < width * 3; ++i) out[i] = static_cast<float>(sum[i]);
  });
  return result;
}

std::vector<EquirectImage> equirectMips(const EquirectImage& level0, int threads) {
  std::vector<EquirectImage> mips;
  const EquirectImage* above = &level0;
  while (above->width > 1 || above->height > 1) {
    EquirectImage mip = resampleEquirect(*above, std::max(1, above->width / 2),
                                         std::max(1, above->height / 2), threads);
    mips.push_back(std::move(mip));
    above = &mips.back();
  }
  return mips;
}

glm::vec2 equirectCoordinates(const glm::vec3& direction) {
  const float length = glm::length(direction);
  return {0.5f + std::atan2(direction.x, -direction.z) / (2.0f * kEnvironmentPiF),
          std::acos(std::clamp(direction.y / length, -1.0f, 1.0f)) / kEnvironmentPiF};
}

glm::vec3 equirectDirection(const glm::vec2& uv) {
  const float phi = (uv.x - 0.5f) * 2.0f * kEnvironmentPiF;
  const float theta = uv.y * kEnvironmentPiF;
  const float sinTheta = std::sin(theta);
  return {sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
}

PrefilteredEnvironment prefilterEnvironment(const EquirectImage& radiance, int threads) {
  requireEquirect(radiance, "prefilterEnvironment");
  threads = std::max(threads, 1);

  EquirectImage level0 =
      radiance.width > kMaxSpecularWidth
          ? resampleEquirect(radiance, kMaxSpecularWidth, kMaxSpecularWidth / 2, threads)
          : radiance;
  std::vector<UnrolledMip> mips;
  mips.push_back(unrolledMip(level0));
  for (const EquirectImage& mip : equirectMips(level0, threads)) mips.push_back(unrolledMip(mip));

  // 1 + floor(log2(width0)) levels in level 0's mip chain.
  const int levels = std::min(
      kSpecularLevels, static_cast<int>(std::bit_width(static_cast<unsigned>(level0.width))));
  PrefilteredEnvironment result;
  result.specular.resize(static_cast<std::size_t>(levels));
  for (int k = 1; k < levels; ++k)
    result.specular[k] = prefilterSpecularLevel(
        mips, k, static_cast<float>(k) / static_cast<float>(levels - 1), threads);
  result.irradiance = irradianceOf(level0, threads);
  result.specular.front() = std::move(level0);
  return result;
}

SpecularBrdfTable specularBrdfTable(int size) {
  if (size < 1)
    throw std::invalid_argument("specularBrdfTable: size " + std::to_string(size) +
                                " (at least 1)");
  SpecularBrdfTable table{size, std::vector<float>(static_cast<std::size_t>(size) * size * 2)};
  std::vector<glm::dvec3> halfVectors(kBrdfTableSamples);
  for (int j = 0; j < size; ++j) {
    const double roughness = (j + 0.5) / size;
    const double alpha = std::max(roughness * roughness, kMinBrdfAlpha);
    for (int s = 0; s < kBrdfTableSamples; ++s)
      halfVectors[s] = ggxHalfVector(s, kBrdfTableSamples, alpha);
    for (int i = 0; i < size; ++i) {
      const double nDotV = (i + 0.5) / size;
      const glm::dvec3 view(std::sqrt(1.0 - nDotV * nDotV), 0.0, nDotV);
      double scale = 0.0, bias = 0.0;
      for (const glm::dvec3& h : halfVectors) {
        const double vDotH = glm::dot(view, h);
        const glm::dvec3 l = 2.0 * vDotH * h - view;
        if (l.z <= 0.0 || vDotH <= 0.0) continue;
        // D Vis F n.l / pdf(l), with pdf(l) = D (n.h) / (4 v.h).
        const double visibilityWeight =
            smithGgxCorrelatedVisibility(l.z, nDotV, alpha) * 4.0 * l.z * vDotH / h.z;
        const double m = 1.0 - vDotH, m2 = m * m;
        const double fresnel = m2 * m2 * m;  // Schlick's (1 - v.h)^5
        scale += (1.0 - fresnel) * visibilityWeight;
        bias += fresnel * visibilityWeight;
      }
      // The estimate of an albedo just under 1 (a smooth surface seen head on) comes out up to
      // 1e-4 over it; more than 1 is never right.
      float* entry = &table.scaleBias[(static_cast<std::size_t>(j) * size + i) * 2];
      entry[0] = static_cast<float>(std::min(scale / kBrdfTableSamples, 1.0));
      entry[1] = static_cast<float>(std::min(bias / kBrdfTableSamples, 1.0));
    }
  }
  return table;
}

std::optional<EnvironmentSun> extractSun(EquirectImage& radiance) {
  requireEquirect(radiance, "extractSun");
  const int width = radiance.width, height = radiance.height;
  const auto texel = [&](int x, int y) {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return glm::dvec3(radiance.rgb[i], radiance.rgb[i + 1], radiance.rgb[i + 2]);
  };
  const auto solidAngle = [&](int y) { return equirectTexelSolidAngle(y, width, height); };
  const auto direction = [&](int x, int y) { return equirectTexelDirection(x, y, width, height); };
  double mean = 0.0, brightest = -1.0;
  int bx = 0, by = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double value = luminanceOf(texel(x, y));
      mean += value * solidAngle(y);
      if (value > brightest) {
        brightest = value;
        bx = x;
        by = y;
      }
    }
  mean /= 4.0 * kEnvironmentPi;
  if (!(brightest > kSunContrast * mean)) return std::nullopt;

  // The texels near the brightest one: the rows it may reach, every column (near a pole a
  // small cone spans them all).
  const glm::dvec3 centre = direction(bx, by);
  const double searchCos = std::cos(static_cast<double>(kSunSearchRadians));
  const double ringCos = std::cos(1.6 * kSunSearchRadians);
  const int rowReach =
      static_cast<int>(std::ceil(1.6 * kSunSearchRadians / kEnvironmentPi * height)) + 1;
  const int y0 = std::max(0, by - rowReach), y1 = std::min(height - 1, by + rowReach);
  glm::dvec3 ring(0.0);
  double ringWeight = 0.0;
  for (int y = y0; y <= y1; ++y)
    for (int x = 0; x < width; ++x) {
      const double c = glm::dot(direction(x, y), centre);
      if (c >= searchCos || c < ringCos) continue;
      ring += texel(x, y) * solidAngle(y);
      ringWeight += solidAngle(y);
    }
  const glm::dvec3 sky = ringWeight > 0.0 ? ring / ringWeight : glm::dvec3(0.0);
  const double threshold = kSunThreshold * brightest;
  glm::dvec3 irradiance(0.0), weighted(0.0);
  std::vector<glm::dvec3> region;
  for (int y = y0; y <= y1; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::dvec3 d = direction(x, y);
      const double c = glm::dot(d, centre);
      const glm::dvec3 value = texel(x, y);
      if (c < searchCos || luminanceOf(value) < threshold) continue;
      const glm::dvec3 excess = glm::max(value - sky, glm::dvec3(0.0)) * solidAngle(y);
      irradiance += excess;
      weighted += d * luminanceOf(excess);
      region.push_back(d);
      const glm::vec3 kept(glm::min(value, sky));
      std::copy(&kept.x, &kept.x + 3, &radiance.rgb[(static_cast<std::size_t>(y) * width + x) * 3]);
    }
  EnvironmentSun sun;
  sun.direction =
      glm::length(weighted) > 0.0 ? glm::vec3(glm::normalize(weighted)) : glm::vec3(centre);
  sun.irradiance = glm::vec3(irradiance);
  // The farthest texel centre from the sun's direction.
  double spread = 1.0;
  for (const glm::dvec3& d : region)
    spread = std::min(spread, glm::dot(d, glm::dvec3(sun.direction)));
  sun.angularRadius = static_cast<float>(std::acos(std::clamp(spread, -1.0, 1.0)));
  return sun;
}

}  // namespace omnishadow
