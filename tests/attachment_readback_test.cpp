// Channels of a frame's RGBA32F attachments into an interleaved image
// (renderer/passes/attachment_readback.h): every copy lands where it says, in every band of rows
// (a height that is no multiple of the band), top row first or in GL's order.
#include "renderer/passes/attachment_readback.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "renderer/gl/gl_debug.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::attachment_readback_test {
namespace {

// A value no two (attachment, x, y, channel) share.
float valueAt(int attachment, int x, int y, int c) {
  return static_cast<float>(attachment * 1000000 + y * 1000 + x * 10 + c);
}

TEST(AttachmentReadback, EveryCopyLandsWhereItSaysInEveryBandAndRowOrder) {
  test_support::sharedRenderer();  // its GL context is current here
  const int w = 19, h = 37;
  FrameTargets targets(w, h, PassOutputs::Aovs);
  ASSERT_GE(targets.attachmentCount(), 4);
  for (int a = 0; a < targets.attachmentCount(); ++a) {
    std::vector<float> texels;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c) texels.push_back(valueAt(a, x, y, c));
    glTextureSubImage2D(targets.color(a), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, texels.data());
  }
  gl::checkErrors("filling the targets");
  // Whole pixels, a pixel's first three channels, one from the middle, two from the end.
  const std::vector<ChannelCopy> copies = {
      {0, 0, 4, 0}, {1, 0, 3, 4}, {1, 3, 1, 7}, {3, 2, 1, 8}, {2, 2, 2, 9}};
  for (const bool glRowOrder : {false, true}) {
    FloatImage image{w, h, std::vector<std::string>(12, "c"), FloatPixels(w * h * 12, -1.0f)};
    readChannels(targets, copies, glRowOrder, image);
    int wrong = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int glY = glRowOrder ? y : h - 1 - y;
        for (const ChannelCopy& copy : copies)
          for (int c = 0; c < copy.count; ++c)
            wrong += image.at(x, y, copy.to + c) != valueAt(copy.attachment, x, glY, copy.from + c);
        wrong += image.at(x, y, 11) != -1.0f;  // no copy goes there
      }
    EXPECT_EQ(wrong, 0) << (glRowOrder ? "GL row order" : "top row first");
  }
}

}  // namespace
}  // namespace omnishadow::attachment_readback_test
