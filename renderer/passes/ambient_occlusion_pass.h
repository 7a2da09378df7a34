#pragma once

#include <glm/glm.hpp>
#include <memory>

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/shader_program.h"

namespace omnishadow {

// Screen-space ambient occlusion (AmbientOcclusion, renderer/scene/light.h): for the opaque
// and masked surfaces a camera sees, the share of the cosine-weighted hemisphere above each
// surface that no surface within `radius` hides, estimated from their depth alone
// (shaders/ambient_occlusion.frag, ground-truth ambient occlusion) at every other pixel of every
// other row. The lighting pass gives each pixel the mean of the four nearest estimates of its
// own surface (shaders/lighting.frag, screenSpaceOcclusion()). What the camera does not see
// occludes nothing. The same depth gives the same estimates, bit for bit.
class AmbientOcclusionPass {
 public:
  AmbientOcclusionPass();

  // Where a caller without the surfaces' depth draws it: a framebuffer with a
  // DEPTH_COMPONENT32F texture (depthTexture()) of that size alone, kept while the size is.
  GLuint depthFramebuffer(int width, int height);
  GLuint depthTexture() const { return ownDepth_.get(); }

  // Estimates from `depth`, the surfaces' reversed depth (0: none) of width x height as
  // `projection` (glClipControl ZERO_TO_ONE) wrote it; `radius` in world units (0: nothing is
  // occluded). Leaves the GL's framebuffer, program, vertex array and unit 0 changed.
  void estimate(GLuint depth, const glm::mat4& projection, int width, int height, float radius);
  // Every pixel of a frame of that size unoccluded, as where no surface is.
  void clear(int width, int height);
  // RG32F, half the frame's size rounded up: for each texel q, the visible share at pixel 2q
  // (1: unoccluded), then that pixel's depth (0: no surface).
  GLuint result() const { return result_.get(); }

 private:
  void resize(int width, int height);

  ShaderProgram estimate_;
  gl::VertexArray empty_;
  gl::Texture result_, ownDepth_;
  gl::Framebuffer framebuffer_, depthFramebuffer_;
  int width_ = 0, height_ = 0, depthWidth_ = 0, depthHeight_ = 0;
};

}  // namespace omnishadow
