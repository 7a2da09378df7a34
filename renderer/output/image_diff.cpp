#include "renderer/output/image_diff.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "renderer/core/errors.h"

namespace omnishadow {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ",") + name;
  return text.empty() ? "none" : text;
}

std::string size(const FloatImage& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

void checkShape(const FloatImage& image, const std::string& label) {
  const std::size_t expected = static_cast<std::size_t>(std::max(image.width, 0)) *
                               std::max(image.height, 0) * image.channels.size();
  if (image.width <= 0 || image.height <= 0 || image.pixels.size() != expected)
    throw std::invalid_argument("compareImages: " + label + " is not a valid " + size(image) +
                                " image");
}

// Pairs of channel indices (in a, in b) to compare, with their names.
struct ChannelPairs {
  std::vector<std::string> names;
  std::vector<int> inA, inB;
};

ChannelPairs pairChannels(const FloatImage& a, const FloatImage& b, const DiffOptions& o) {
  ChannelPairs pairs;
  if (o.channels.empty()) {
    for (std::size_t c = 0; c < a.channels.size(); ++c) {
      const int other = b.channelIndex(a.channels[c]);
      if (other < 0) continue;
      pairs.names.push_back(a.channels[c]);
      pairs.inA.push_back(static_cast<int>(c));
      pairs.inB.push_back(other);
    }
    if (pairs.names.empty())
      throw InputError(o.labelA + " and " + o.labelB + " share no channel (" + o.labelA + ": " +
                       joined(a.channels) + "; " + o.labelB + ": " + joined(b.channels) + ")");
    return pairs;
  }
  for (const std::string& name : o.channels) {
    if (std::find(pairs.names.begin(), pairs.names.end(), name) != pairs.names.end())
      throw InputError("channel \"" + name + "\" is requested twice");
    const int inA = a.channelIndex(name), inB = b.channelIndex(name);
    if (inA < 0)
      throw InputError(o.labelA + ": no channel \"" + name + "\" (has " + joined(a.channels) + ")");
    if (inB < 0)
      throw InputError(o.labelB + ": no channel \"" + name + "\" (has " + joined(b.channels) + ")");
    pairs.names.push_back(name);
    pairs.inA.push_back(inA);
    pairs.inB.push_back(inB);
  }
  return pairs;
}

double absDifference(float x, float y) {
  const bool xNan = std::isnan(x), yNan = std::isnan(y);
  if (xNan || yNan) return xNan && yNan ? 0.0 : kInfinity;
  if (x == y) return 0.0;  // also equal infinities, whose difference would be NaN
  return std::fabs(static_cast<double>(x) - static_cast<double>(y));
}

// Running sums for one set of channels.
struct Accumulator {
  double sum = 0.0, sumSquares = 0.0, max = 0.0;
  std::uint64_t failing = 0;
  int maxX = -1, maxY = -1;

  void addPixel(double difference, double threshold, int x, int y) {
    if (difference > threshold) ++failing;
    if (difference > max) {
      max = difference;
      maxX = x;
      maxY = y;
    }
  }

  DiffStats stats(std::vector<std::string> channels, std::size_t pixels, double peak) const {
    DiffStats s;
    const double samples = static_cast<double>(pixels) * static_cast<double>(channels.size());
    s.channels = std::move(channels);
    s.maxAbs = max;
    s.meanAbs = sum / samples;
    s.rmse = std::sqrt(sumSquares / samples);
    s.psnr = s.rmse == 0.0 ? kInfinity : 10.0 * std::log10(peak * peak / (s.rmse * s.rmse));
    s.failingPixels = failing;
    s.failingFraction = static_cast<double>(failing) / static_cast<double>(pixels);
    s.maxX = maxX;
    s.maxY = maxY;
    return s;
  }
};

double referencePeak(const FloatImage& a, const std::vector<int>& channels) {
  double peak = -kInfinity;
  const std::size_t stride = a.channels.size();
  for (std::size_t p = 0; p < a.pixels.size(); p += stride)
    for (int c : channels) {
      const float value = a.pixels[p + static_cast<std::size_t>(c)];
      if (std::isfinite(value)) peak = std::max(peak, static_cast<double>(value));
    }
  return peak > 0.0 ? peak : 1.0;
}

}  // namespace

DiffResult compareImages(const FloatImage& a, const FloatImage& b, const DiffOptions& o) {
  checkShape(a, o.labelA);
  checkShape(b, o.labelB);
  if (a.width != b.width || a.height != b.height)
    throw InputError(o.labelB + ": size " + size(b) + " differs from " + o.labelA + "'s " +
                     size(a));
  const ChannelPairs pairs = pairChannels(a, b, o);
  const std::size_t count = pairs.names.size();

  DiffResult result;
  result.width = a.width;
  result.height = a.height;
  result.peak = o.peak > 0.0 ? o.peak : referencePeak(a, pairs.inA);
  result.pixelMaxAbs.resize(static_cast<std::size_t>(a.width) * a.height);

  Accumulator overall;
  std::vector<Accumulator> channels(o.perChannel ? count : 0);
  const std::size_t strideA = a.channels.size(), strideB = b.channels.size();
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const std::size_t pixel = static_cast<std::size_t>(y) * a.width + x;
      const float* pa = a.pixels.data() + pixel * strideA;
      const float* pb = b.pixels.data() + pixel * strideB;
      double pixelMax = 0.0;
      for (std::size_t c = 0; c < count; ++c) {
        const double d = absDifference(pa[pairs.inA[c]], pb[pairs.inB[c]]);
        overall.sum += d;
        overall.sumSquares += d * d;
        pixelMax = std::max(pixelMax, d);
        if (o.perChannel) {
          Accumulator& channel = channels[c];
          channel.sum += d;
          channel.sumSquares += d * d;
          channel.addPixel(d, o.threshold, x, y);
        }
      }
      overall.addPixel(pixelMax, o.threshold, x, y);
      result.pixelMaxAbs[pixel] = static_cast<float>(pixelMax);
    }
  }

  const std::size_t pixels = result.pixelMaxAbs.size();
  result.overall = overall.stats(pairs.names, pixels, result.peak);
  for (std::size_t c = 0; c < channels.size(); ++c)
    result.perChannel.push_back(channels[c].stats({pairs.names[c]}, pixels, result.peak));
  return result;
}

std::array<std::uint8_t, 3> heatColor(double t) {
  // Black, then matplotlib's inferno at t = 0.1, 0.2, ..., 1.
  static constexpr std::uint8_t kRamp[11][3] = {
      {0, 0, 0},     {22, 11, 57},   {66, 10, 104},  {106, 23, 110}, {147, 38, 103}, {188, 55, 84},
      {221, 81, 58}, {243, 120, 25}, {252, 165, 10}, {246, 215, 70}, {252, 255, 164}};
  if (std::isnan(t)) t = 1.0;
  t = std::clamp(t, 0.0, 1.0) * 10.0;
  const int i = std::min(static_cast<int>(t), 9);
  const double f = t - i;
  std::array<std::uint8_t, 3> color{};
  for (int c = 0; c < 3; ++c) {
    const double value = kRamp[i][c] + f * (kRamp[i + 1][c] - kRamp[i][c]);
    color[c] = static_cast<std::uint8_t>(std::lround(value));
  }
  return color;
}

std::vector<std::uint8_t> heatMap(const DiffResult& result, double scale) {
  if (!(scale > 0.0)) throw std::invalid_argument("heatMap: the scale must be positive");
  std::vector<std::uint8_t> rgb;
  rgb.reserve(result.pixelMaxAbs.size() * 3);
  for (float difference : result.pixelMaxAbs) {
    const auto color = heatColor(static_cast<double>(difference) / scale);
    rgb.insert(rgb.end(), color.begin(), color.end());
  }
  return rgb;
}

double defaultHeatScale(const DiffResult& result) {
  const double max = result.overall.maxAbs;
  return std::isfinite(max) && max > 0.0 ? max : 1.0;
}

}  // namespace omnishadow
