#include "renderer/passes/ambient_occlusion_pass.h"

#include <string>

#include "renderer/core/errors.h"
#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"

namespace omnishadow {

namespace {

gl::Texture makeTexture(GLenum format, int width, int height) {
  gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.get(), 1, format, width, height);
  return texture;
}

// `framebuffer` with `texture` at `attachment` alone, checked complete.
void attach(GLuint framebuffer, GLenum attachment, GLuint texture, int width, int height) {
  glNamedFramebufferTexture(framebuffer, attachment, texture, 0);
  const GLenum buffer = attachment == GL_DEPTH_ATTACHMENT ? GL_NONE : attachment;
  glNamedFramebufferDrawBuffers(framebuffer, 1, &buffer);
  if (glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("cannot create the " + std::to_string(width) + "x" + std::to_string(height) +
                      " ambient occlusion targets");
}

// The estimate's size along an axis of the frame: a texel for each 2 pixels, the last one
// alone where the frame's size is odd.
int halfSize(int size) {
  return (size + 1) / 2;
}

}  // namespace

AmbientOcclusionPass::AmbientOcclusionPass()
    : estimate_("fullscreen.vert", "ambient_occlusion.frag", contract::shaderContractDefines()),
      empty_(gl::createVertexArray()) {}

void AmbientOcclusionPass::resize(int width, int height) {
  if (width == width_ && height == height_) return;
  framebuffer_ = gl::createFramebuffer();
  result_ = makeTexture(GL_RG32F, halfSize(width), halfSize(height));
  attach(framebuffer_.get(), GL_COLOR_ATTACHMENT0, result_.get(), halfSize(width),
         halfSize(height));
  width_ = width;
  height_ = height;
}

GLuint AmbientOcclusionPass::depthFramebuffer(int width, int height) {
  if (width != depthWidth_ || height != depthHeight_) {
    depthFramebuffer_ = gl::createFramebuffer();
    ownDepth_ = makeTexture(GL_DEPTH_COMPONENT32F, width, height);
    attach(depthFramebuffer_.get(), GL_DEPTH_ATTACHMENT, ownDepth_.get(), width, height);
    depthWidth_ = width;
    depthHeight_ = height;
  }
  return depthFramebuffer_.get();
}

void AmbientOcclusionPass::clear(int width, int height) {
  resize(width, height);
  const float none[4] = {1.0f, 0.0f, 0.0f, 0.0f};
  glClearNamedFramebufferfv(framebuffer_.get(), GL_COLOR, 0, none);
}

void AmbientOcclusionPass::estimate(GLuint depth, const glm::mat4& projection, int width,
                                    int height, float radius) {
  if (!(radius > 0.0f)) {
    clear(width, height);
    return;
  }
  resize(width, height);
  gl::RasterState state;
  state.depth.test = false;  // full-screen triangles, no depth attachment
  state.viewport = {0, 0, halfSize(width), halfSize(height)};
  state.apply();
  glBindVertexArray(empty_.get());
  // texelFetch alone: no sampler state is read, but a sampler left bound must not compare.
  glBindSampler(0, 0);
  glBindTextureUnit(0, depth);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  estimate_.use();
  estimate_.set("uInverseProjection", glm::inverse(projection));
  estimate_.set("uRadius", radius);
  // Pixels per world unit at view distance 1 (perspective) or anywhere (orthographic): the
  // projection's vertical scale over half the image's height.
  estimate_.set("uPixelsPerUnit", projection[1][1] * 0.5f * static_cast<float>(height));
  estimate_.set("uOrthographic", projection[3][3] == 1.0f ? 1 : 0);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  gl::RasterState::restoreDefaults();
  gl::checkErrors("the ambient occlusion pass");
}

}  // namespace omnishadow
