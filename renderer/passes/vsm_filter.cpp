#include "renderer/passes/vsm_filter.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/passes/texel_scissor.h"

namespace omnishadow {

int VsmFilter::spread(float radiusTexels) {
  return static_cast<int>(std::ceil(radiusTexels));
}

VsmFilter::VsmFilter(double maxScratchBytes)
    : maxScratchBytes_(maxScratchBytes),
      framebuffer_(gl::createFramebuffer()),
      empty_(gl::createVertexArray()),
      nearest_(gl::createSampler()) {
  glSamplerParameteri(nearest_.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(nearest_.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(nearest_.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(nearest_.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

const ShaderProgram& VsmFilter::program(int layers) {
  auto& slot = programs_[static_cast<std::size_t>(layers)];
  if (!slot) {
    auto defines = contract::shaderContractDefines();
    defines.push_back("VSM_LAYERS " + std::to_string(layers));
    slot = std::make_unique<ShaderProgram>("fullscreen.vert", "vsm_blur.frag", defines);
  }
  return *slot;
}

void VsmFilter::blur(const ShadowGroupTextures& group, const LightShadowPlan& plan,
                     float radiusTexels) {
  const int taps = spread(radiusTexels);
  if (taps < 1 || !group.moments) return;
  const int n = group.key.resolution;

  // The light's layers that hold something besides the cleared moments, and where: the shadow
  // pass drew there and grew it by the blur's spread, so the vertical pass writes all of it.
  std::vector<int> layers;
  TexelRect written;
  for (int layer = 0; layer < plan.layerCount; ++layer) {
    const TexelRect& rect = group.written[static_cast<std::size_t>(plan.firstLayer + layer)];
    if (rect.empty()) continue;
    layers.push_back(layer);
    written = written.united(rect);
  }
  if (layers.empty()) return;
  // The vertical pass reads the horizontal one's rows out to its taps.
  const TexelRect rows = written.grown(0, taps, n);

  const double layerBytes = 8.0 * n * n;  // RG32F
  const int perDraw = std::clamp(static_cast<int>(maxScratchBytes_ / layerBytes), 1,
                                 std::min(static_cast<int>(layers.size()), kMaxLayersPerDraw));
  if (scratchSize_ != n || scratchLayers_ < perDraw) {
    scratch_ = gl::createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(scratch_.get(), 1, GL_RG32F, n, n, perDraw);
    scratchSize_ = n;
    scratchLayers_ = perDraw;
  }
  // The light's layers as a plain 2D array, cube faces included (a view shares the storage).
  GLuint viewId = 0;
  glGenTextures(1, &viewId);
  const gl::Texture view(viewId);
  glTextureView(view.get(), GL_TEXTURE_2D_ARRAY, group.moments.get(), GL_RG32F, 0, 1,
                static_cast<GLuint>(plan.firstLayer), static_cast<GLuint>(plan.layerCount));

  const GLuint fb = framebuffer_.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  gl::RasterState state;
  state.depth.test = false;  // a fullscreen triangle, no depth attachment
  state.viewport = {0, 0, n, n};
  state.apply();
  glBindVertexArray(empty_.get());
  constexpr auto unit = static_cast<GLuint>(contract::kVsmSourceUnit);
  glBindSampler(unit, nearest_.get());

  // One direction over `count` layers: output i reads `source`'s layer sourceLayers[i] and
  // goes to `target`'s layer targetLayers[i], within `rect`.
  auto pass = [&](const ShaderProgram& p, GLuint source, const int* sourceLayers, GLuint target,
                  const int* targetLayers, int count, bool horizontal, const TexelRect& rect) {
    std::array<GLenum, kMaxLayersPerDraw> buffers{};
    for (int i = 0; i < count; ++i) {
      const auto attachment = static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i);
      glNamedFramebufferTextureLayer(fb, attachment, target, 0, targetLayers[i]);
      buffers[static_cast<std::size_t>(i)] = attachment;
    }
    glNamedFramebufferDrawBuffers(fb, count, buffers.data());
    glBindTextureUnit(unit, source);
    glProgramUniform1iv(p.id(), p.location("uSourceLayers"), count, sourceLayers);
    glProgramUniform2i(p.id(), p.location("uStep"), horizontal ? 1 : 0, horizontal ? 0 : 1);
    scissorTo(rect);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  };
  std::array<int, kMaxLayersPerDraw> scratchLayers{}, targetLayers{};
  for (int i = 0; i < kMaxLayersPerDraw; ++i) scratchLayers[static_cast<std::size_t>(i)] = i;
  for (std::size_t first = 0; first < layers.size(); first += static_cast<std::size_t>(perDraw)) {
    const int count = std::min(perDraw, static_cast<int>(layers.size() - first));
    for (int i = 0; i < count; ++i)
      targetLayers[static_cast<std::size_t>(i)] = plan.firstLayer + layers[first + i];
    const ShaderProgram& p = program(count);
    p.use();
    p.set("uRadius", taps);
    p.set("uSigma", std::max(0.5f, radiusTexels * 0.5f));
    pass(p, view.get(), &layers[first], scratch_.get(), scratchLayers.data(), count, true, rows);
    pass(p, scratch_.get(), scratchLayers.data(), group.moments.get(), targetLayers.data(), count,
         false, written);
  }
  for (int i = 0; i < kMaxLayersPerDraw; ++i)
    glNamedFramebufferTexture(fb, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i), 0, 0);
  glBindTextureUnit(unit, 0);
  glBindSampler(unit, 0);
  gl::RasterState::restoreDefaults();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("filtering the vsm moments of a light");
}

}  // namespace omnishadow
