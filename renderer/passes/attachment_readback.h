#pragma once

#include <vector>

#include "renderer/output/image_writer.h"
#include "renderer/passes/lighting_pass.h"

namespace omnishadow {

// `count` channels of a frame target's RGBA32F attachment, from channel `from`, into an
// interleaved image's channels from `to`.
struct ChannelCopy {
  int attachment = 0;
  int from = 0;
  int count = 1;
  int to = 0;
};

// Reads the attachments that `copies` name and writes every copy into `image` (the targets'
// size; first row = top unless `glRowOrder`). The attachments are read a band of rows at a time
// into buffers that stay in cache while the band's channels go to their places: reading each
// attachment whole and then spreading its channels over the image took a fresh buffer per
// attachment and a pass over the whole interleaved image per attachment.
void readChannels(const FrameTargets& targets, const std::vector<ChannelCopy>& copies,
                  bool glRowOrder, FloatImage& image);

}  // namespace omnishadow
