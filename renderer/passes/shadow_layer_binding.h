#pragma once

#include <GL/glcorearb.h>

#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/passes/shadow_textures.h"
#include "renderer/view/caster_culling.h"

namespace omnishadow {

// Attaches one light's layers of a shadow group to the shadow pass's framebuffer, one layer or
// all of them at once, and clears each layer the first time it is attached.
//
// Layers are cleared through the framebuffer, not with glClearTexSubImage: llvmpipe then
// clears tile by tile in its rasterizer threads, in the pass that draws, instead of sweeping
// the texture on the calling thread first. Clears obey the depth and color write masks: the
// pass's raster state must be applied before the first bind.
//
// Each layer is cleared only where it may hold something other than the cleared values (the
// group's `written` texels: where its last pass drew, the whole layer for a new texture,
// nothing after clearShadowTextures()), and afterwards holds something only where this pass
// may draw (`casterTexels`), grown by `spread` texels where a later pass spreads what it drew
// (the VSM blur of moments, which then filters only those texels). A 1024² face costs llvmpipe
// about 0.4 ms to clear, six per point light and frame, mostly for texels no caster reaches.
// Layers bound all at once are cleared where any of them may hold something.
class ShadowLayerBinding {
 public:
  static constexpr int kAllLayers = -1;
  // `casterTexels`: per layer of this light, the texels its casters may cover in this pass.
  ShadowLayerBinding(GLuint framebuffer, ShadowGroupTextures& target, int firstLayer,
                     int layerCount, std::vector<TexelRect> casterTexels, int spread);
  // `layer`: 0..layerCount-1 of this light, or kAllLayers. Nothing happens when it is bound.
  void bind(int layer);
  // Clears the layers no bind reached (views nothing was drawn into).
  void clearUnbound();
  void detach();

 private:
  void clear(const TexelRect& texels);
  // What this pass may leave other than the cleared values in `layer`.
  TexelRect drawn(int layer) const;
  TexelRect& written(int layer) {
    return target_.written[static_cast<std::size_t>(firstLayer_ + layer)];
  }
  gl::Texture layersView(const gl::Texture& texture, GLenum format) const;

  GLuint framebuffer_;
  ShadowGroupTextures& target_;
  int firstLayer_, layerCount_;
  std::vector<TexelRect> casterTexels_;
  int spread_;
  int bound_ = kAllLayers - 1;  // nothing
  bool allCleared_ = false;
  std::vector<bool> cleared_;
  // Views of just this light's layers: a layered attachment of the whole texture would clear
  // every light's.
  gl::Texture depthLayers_, momentLayers_;
};

}  // namespace omnishadow
