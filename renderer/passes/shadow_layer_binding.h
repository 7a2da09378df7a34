#pragma once

#include <GL/glcorearb.h>

#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/passes/shadow_textures.h"

namespace omnishadow {

// Attaches one light's layers of a shadow group to the shadow pass's framebuffer, one layer or
// all of them at once, and clears each layer the first time it is attached.
//
// Layers are cleared through the framebuffer, not with glClearTexSubImage: llvmpipe then
// clears tile by tile in its rasterizer threads, in the pass that draws, instead of sweeping
// the texture on the calling thread first. Clears obey the depth and color write masks: the
// pass's raster state must be applied before the first bind.
class ShadowLayerBinding {
 public:
  static constexpr int kAllLayers = -1;

  ShadowLayerBinding(GLuint framebuffer, const ShadowGroupTextures& target, int firstLayer,
                     int layerCount);

  // `layer`: 0..layerCount-1 of this light, or kAllLayers. Nothing happens when it is bound.
  void bind(int layer);
  // Clears the layers no bind reached (views nothing was drawn into).
  void clearUnbound();
  void detach();

 private:
  void clear();
  gl::Texture layersView(const gl::Texture& texture, GLenum format) const;

  GLuint framebuffer_;
  const ShadowGroupTextures& target_;
  int firstLayer_, layerCount_;
  int bound_ = kAllLayers - 1;  // nothing
  bool allCleared_ = false;
  std::vector<bool> cleared_;
  // Views of just this light's layers: a layered attachment of the whole texture would clear
  // every light's.
  gl::Texture depthLayers_, momentLayers_;
};

}  // namespace omnishadow
