#pragma once

#include <array>
#include <memory>

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/shader_program.h"
#include "renderer/passes/shadow_textures.h"

namespace omnishadow {

// Pre-filters the moments of a vsm light with a separable Gaussian (sigma = radius / 2, taps out
// to the radius). Cube faces are filtered one by one, clamped at their edges; sampling then
// filters across faces with seamless cube filtering.
//
// On llvmpipe a blur fragment's fixed cost is about that of five taps, and most texels of most
// faces hold the cleared moments (1, 1), which the blur gives back as they are: each weight
// times 1, summed in the order of the weights' own sum, is that sum, and x / x is 1 where
// division is IEEE's, as on llvmpipe (where it is not, the cleared value left in place is the
// better one). So each direction is one draw over all of a light's layers that hold something
// (the group's `written` texels, which the shadow pass grew by spread()), a color output per
// layer, scissored to where they hold it: pictures are bit for bit those of a blur of every
// texel of every layer (tests/vsm_filter_test.cpp).
class VsmFilter {
 public:
  static constexpr int kMaxLayersPerDraw = 6;  // a cube map; GL guarantees 8 draw buffers
  // The scratch layers of one draw take at most this much (or one layer): six of a 1024² cube,
  // two of a 2048² one, and one, as a draw per layer took, beyond.
  static constexpr double kMaxScratchBytes = 64.0 * 1024 * 1024;

  // Texels the blur of `radiusTexels` moves moments by: its taps on each side.
  static int spread(float radiusTexels);

  explicit VsmFilter(double maxScratchBytes = kMaxScratchBytes);
  void blur(const ShadowGroupTextures& group, const LightShadowPlan& plan, float radiusTexels);

 private:
  // The program for `layers` layers per draw, compiled the first time a light needs it.
  const ShaderProgram& program(int layers);

  double maxScratchBytes_;
  std::array<std::unique_ptr<ShaderProgram>, kMaxLayersPerDraw + 1> programs_;
  gl::Framebuffer framebuffer_;
  gl::VertexArray empty_;
  gl::Sampler nearest_;  // texel centres, clamped at the edges
  gl::Texture scratch_;  // RG32F layers of the group's size: the horizontal pass's output
  int scratchSize_ = 0;
  int scratchLayers_ = 0;
};

}  // namespace omnishadow
