#pragma once

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/shader_program.h"
#include "renderer/passes/shadow_textures.h"

namespace omnishadow {

// Pre-filters the moments of a vsm light with a separable Gaussian (sigma = radius / 2, taps out
// to the radius), layer by layer. Cube faces are filtered one by one, clamped at their edges;
// sampling then filters across faces with seamless cube filtering.
class VsmFilter {
 public:
  VsmFilter();
  void blur(const ShadowGroupTextures& group, const LightShadowPlan& plan, float radiusTexels);

 private:
  ShaderProgram program_;
  gl::Framebuffer framebuffer_;
  gl::VertexArray empty_;
  gl::Texture scratch_;  // one RG32F layer of the group's size
  int scratchSize_ = 0;
};

}  // namespace omnishadow
