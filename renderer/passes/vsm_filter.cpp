#include "renderer/passes/vsm_filter.h"

#include <cmath>

#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"

namespace omnishadow {

VsmFilter::VsmFilter()
    : program_("fullscreen.vert", "vsm_blur.frag", contract::shaderContractDefines()),
      framebuffer_(gl::createFramebuffer()),
      empty_(gl::createVertexArray()) {}

void VsmFilter::blur(const ShadowGroupTextures& group, const LightShadowPlan& plan,
                     float radiusTexels) {
  const int taps = static_cast<int>(std::ceil(radiusTexels));
  if (taps < 1 || !group.moments) return;
  const int n = group.key.resolution;
  if (scratchSize_ != n) {
    scratch_ = gl::createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(scratch_.get(), 1, GL_RG32F, n, n, 1);
    scratchSize_ = n;
  }
  // The layers as a plain 2D array, cube faces included (a texture view shares the storage).
  GLuint viewId = 0;
  glGenTextures(1, &viewId);
  const gl::Texture view(viewId);
  glTextureView(view.get(), GL_TEXTURE_2D_ARRAY, group.moments.get(), GL_RG32F, 0, 1,
                static_cast<GLuint>(plan.firstLayer), static_cast<GLuint>(plan.layerCount));

  const GLuint fb = framebuffer_.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  glNamedFramebufferDrawBuffer(fb, GL_COLOR_ATTACHMENT0);
  gl::RasterState state;
  state.depth.test = false;  // a fullscreen triangle, no depth attachment
  state.viewport = {0, 0, n, n};
  state.apply();
  glBindVertexArray(empty_.get());
  program_.use();
  program_.set("uRadius", taps);
  program_.set("uSigma", std::max(0.5f, radiusTexels * 0.5f));
  constexpr auto unit = static_cast<GLuint>(contract::kVsmSourceUnit);
  glBindSampler(unit, 0);
  const GLint horizontal = program_.location("uStep");
  for (int layer = 0; layer < plan.layerCount; ++layer) {
    glNamedFramebufferTextureLayer(fb, GL_COLOR_ATTACHMENT0, scratch_.get(), 0, 0);
    glBindTextureUnit(unit, view.get());
    program_.set("uLayer", layer);
    glProgramUniform2i(program_.id(), horizontal, 1, 0);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    glNamedFramebufferTextureLayer(fb, GL_COLOR_ATTACHMENT0, group.moments.get(), 0,
                                   plan.firstLayer + layer);
    glBindTextureUnit(unit, scratch_.get());
    program_.set("uLayer", 0);
    glProgramUniform2i(program_.id(), horizontal, 0, 1);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindTextureUnit(unit, 0);
  gl::RasterState::restoreDefaults();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("filtering the vsm moments of a light");
}

}  // namespace omnishadow
