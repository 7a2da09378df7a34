#include "renderer/passes/shadow_layer_binding.h"

#include <utility>

#include "renderer/passes/texel_scissor.h"

namespace omnishadow {

ShadowLayerBinding::ShadowLayerBinding(GLuint framebuffer, ShadowGroupTextures& target,
                                       int firstLayer, int layerCount,
                                       std::vector<TexelRect> casterTexels, int spread)
    : framebuffer_(framebuffer),
      target_(target),
      firstLayer_(firstLayer),
      layerCount_(layerCount),
      casterTexels_(std::move(casterTexels)),
      spread_(spread),
      cleared_(static_cast<std::size_t>(layerCount), false) {}

gl::Texture ShadowLayerBinding::layersView(const gl::Texture& texture, GLenum format) const {
  GLuint id = 0;
  glGenTextures(1, &id);
  glTextureView(id, GL_TEXTURE_2D_ARRAY, texture.get(), format, 0, 1,
                static_cast<GLuint>(firstLayer_), static_cast<GLuint>(layerCount_));
  return gl::Texture(id);
}

void ShadowLayerBinding::clear(const TexelRect& texels) {
  if (texels.empty()) return;
  scissorTo(texels);
  glClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &kClearedDepth);
  if (target_.key.moments) glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, kClearedMoments);
  gl::Scissor{}.apply();
}

TexelRect ShadowLayerBinding::drawn(int layer) const {
  return casterTexels_[static_cast<std::size_t>(layer)].grown(spread_, spread_,
                                                              target_.key.resolution);
}

void ShadowLayerBinding::bind(int layer) {
  if (layer == bound_) return;
  bound_ = layer;
  const bool moments = target_.key.moments;
  if (layer == kAllLayers) {
    depthLayers_ = layersView(target_.depth, depthInternalFormat(target_.key.format));
    glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depthLayers_.get(), 0);
    if (moments) momentLayers_ = layersView(target_.moments, GL_RG32F);
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, moments ? momentLayers_.get() : 0,
                              0);
    TexelRect anyWritten;
    for (int l = 0; l < layerCount_; ++l) anyWritten = anyWritten.united(written(l));
    clear(anyWritten);
    for (int l = 0; l < layerCount_; ++l) written(l) = drawn(l);
    allCleared_ = true;
    return;
  }
  glNamedFramebufferTextureLayer(framebuffer_, GL_DEPTH_ATTACHMENT, target_.depth.get(), 0,
                                 firstLayer_ + layer);
  if (moments)
    glNamedFramebufferTextureLayer(framebuffer_, GL_COLOR_ATTACHMENT0, target_.moments.get(), 0,
                                   firstLayer_ + layer);
  else
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, 0, 0);
  if (!cleared_[static_cast<std::size_t>(layer)]) {
    clear(written(layer));
    written(layer) = drawn(layer);
    cleared_[static_cast<std::size_t>(layer)] = true;
  }
}

void ShadowLayerBinding::clearUnbound() {
  if (allCleared_) return;
  for (int layer = 0; layer < layerCount_; ++layer)
    if (!cleared_[static_cast<std::size_t>(layer)]) bind(layer);
}

void ShadowLayerBinding::detach() {
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, 0, 0);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, 0, 0);
  bound_ = kAllLayers - 1;
}

}  // namespace omnishadow
