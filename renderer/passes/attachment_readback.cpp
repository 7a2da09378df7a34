#include "renderer/passes/attachment_readback.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <cstddef>
#include <cstring>

namespace omnishadow {
namespace {

constexpr int kBandRows = 16;  // a 1280-pixel row of RGBA32F is 20 KiB

// One copy over the `count` pixels of one row: `from` and `to` point at its first pixel's
// channels, `stride` is the image's channels per pixel.
template <int Count>
void copyRow(const float* from, float* to, std::size_t stride, int count) {
  // memcpy of a fixed size: one move of the pixel's channels, where a loop of channels was a
  // load and a store each (the compiler cannot tell that `to` and `from` never overlap).
  for (int x = 0; x < count; ++x, from += 4, to += stride)
    std::memcpy(to, from, Count * sizeof(float));
}

}  // namespace

void readChannels(const FrameTargets& targets, const std::vector<ChannelCopy>& copies,
                  bool glRowOrder, FloatImage& image) {
  const int w = targets.width(), h = targets.height();
  const std::size_t stride = image.channels.size();
  // The attachments the copies read, each once, and each copy's among them.
  std::vector<int> attachments;
  std::vector<std::size_t> source;
  for (const ChannelCopy& copy : copies) {
    const auto found = std::find(attachments.begin(), attachments.end(), copy.attachment);
    source.push_back(static_cast<std::size_t>(found - attachments.begin()));
    if (found == attachments.end()) attachments.push_back(copy.attachment);
  }
  const std::size_t bandFloats = static_cast<std::size_t>(w) * kBandRows * 4;
  std::vector<FloatPixels> bands(attachments.size(), FloatPixels(bandFloats));
  for (int y0 = 0; y0 < h; y0 += kBandRows) {
    const int rows = std::min(kBandRows, h - y0);
    for (std::size_t a = 0; a < attachments.size(); ++a)
      glGetTextureSubImage(targets.color(attachments[a]), 0, 0, y0, 0, w, rows, 1, GL_RGBA,
                           GL_FLOAT, static_cast<GLsizei>(bandFloats * sizeof(float)),
                           bands[a].data());
    // Row by row, every copy of the row: an image row (up to 36 channels, 180 KiB at 1280
    // pixels) stays in cache while its channels arrive; copy by copy, each copy went over the
    // whole band of the image (16 rows) again.
    for (int r = 0; r < rows; ++r) {
      const int y = glRowOrder ? y0 + r : h - 1 - (y0 + r);
      for (std::size_t k = 0; k < copies.size(); ++k) {
        const ChannelCopy& copy = copies[k];
        const float* from =
            bands[source[k]].data() + static_cast<std::size_t>(r) * w * 4 + copy.from;
        float* to = image.pixels.data() + static_cast<std::size_t>(y) * w * stride + copy.to;
        switch (copy.count) {
          case 1:
            copyRow<1>(from, to, stride, w);
            break;
          case 2:
            copyRow<2>(from, to, stride, w);
            break;
          case 3:
            copyRow<3>(from, to, stride, w);
            break;
          default:
            copyRow<4>(from, to, stride, w);
            break;
        }
      }
    }
  }
}

}  // namespace omnishadow
