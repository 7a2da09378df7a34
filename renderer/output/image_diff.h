#pragma once

// Per-pixel comparison of two images, as `omnishadow diff` reports it: a small pure library
// (no files, no printing) so that tests and tools can use it directly.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "renderer/output/image_writer.h"

namespace omnishadow {

struct DiffOptions {
  // Channels to compare, by name; each must be in both images. Empty: every channel of `a`
  // that `b` also has, in `a`'s order.
  std::vector<std::string> channels;
  // A pixel "fails" when its absolute difference (the maximum over the compared channels, or
  // the one channel's for per-channel statistics) is strictly above this.
  double threshold = 0.0;
  // PSNR peak. 0: the maximum of `a`'s values over the compared channels (1 when that maximum
  // is not a positive finite number). Callers pass 1 for normalized 8-bit images.
  double peak = 0.0;
  bool perChannel = false;  // also gather DiffResult::perChannel
  // How messages name the images ("a.png"), as in "b.png: no channel \"Z\"".
  std::string labelA = "A", labelB = "B";
};

// Statistics over a set of channels. Differences are |a - b| in double precision; two NaNs, or
// two infinities of the same sign, are equal; otherwise a non-finite value on either side is an
// infinite difference.
struct DiffStats {
  std::vector<std::string> channels;  // the channels these statistics cover
  double maxAbs = 0.0;                // largest absolute difference
  double meanAbs = 0.0;               // mean over every pixel and channel
  double rmse = 0.0;                  // root of the mean squared difference, likewise
  double psnr = 0.0;                  // 10 log10(peak^2 / rmse^2); +infinity when rmse is 0
  std::uint64_t failingPixels = 0;    // pixels whose difference is above the threshold
  double failingFraction = 0.0;       // failingPixels / (width * height)
  int maxX = -1, maxY = -1;           // first pixel (row by row, from the top) with maxAbs; -1
                                      // when maxAbs is 0
};

struct DiffResult {
  int width = 0, height = 0;
  double peak = 1.0;  // the PSNR peak used
  DiffStats overall;  // over all compared channels; a pixel's difference is its channel maximum
  std::vector<DiffStats> perChannel;  // one per compared channel, with DiffOptions::perChannel
  std::vector<float> pixelMaxAbs;     // width * height: each pixel's overall difference
};

// Compares `a` (the reference) with `b`. Throws InputError, naming the images by their labels,
// when the sizes differ, the images share no channel, or a requested channel is missing.
DiffResult compareImages(const FloatImage& a, const FloatImage& b, const DiffOptions& options);

// The heat-map colour of t in [0, 1] (clamped; NaN counts as 1): black at 0, then an
// approximation of matplotlib's "inferno" through its colours at t = 0.1, 0.2, ..., 1
// (#160b39 #420a68 #6a176e #932667 #bc3754 #dd513a #f37819 #fca50a #f6d746 #fcffa4),
// interpolated linearly in 8-bit sRGB.
std::array<std::uint8_t, 3> heatColor(double t);

// The heat map of a comparison as 8-bit sRGB RGB pixels, row by row from the top: each pixel is
// heatColor(difference / scale). `scale` must be positive.
std::vector<std::uint8_t> heatMap(const DiffResult& result, double scale);

// The scale `omnishadow diff` uses by default: the overall maximum difference when it is
// positive and finite, else 1.
double defaultHeatScale(const DiffResult& result);

}  // namespace omnishadow
