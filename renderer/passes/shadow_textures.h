#pragma once

#include <GL/glcorearb.h>

#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/scene/light.h"
#include "renderer/view/caster_culling.h"
#include "renderer/view/cube_distances.h"
#include "renderer/view/shadow_plan.h"

namespace omnishadow {

// The GL internal format of a depth format.
GLenum depthInternalFormat(DepthFormat format);

// GL textures of one group.

struct ShadowGroupTextures {
  ShadowGroupKey key;
  int layers = 0;
  gl::Texture depth;    // GL_TEXTURE_CUBE_MAP_ARRAY or GL_TEXTURE_2D_ARRAY
  gl::Texture moments;  // same target, GL_RG32F, when key.moments
  // Per texture layer: the texels that may hold something other than the cleared values, which
  // the next pass into the layer must clear (ShadowLayerBinding). The whole layer for a new
  // texture, whose contents GL leaves undefined (none where the pool knows them to be zeros);
  // none after clearShadowTextures().
  std::vector<TexelRect> written;
};

// The cleared values: depth 0 (reversed depth: nothing nearer than the far plane) and, for
// moments (VSM), the moments of the far plane.
inline constexpr float kClearedDepth = 0.0f;
inline constexpr float kClearedMoments[4] = {1.0f, 1.0f, 0.0f, 0.0f};

// Clears every layer of the group that may hold a written texel (llvmpipe does it in its
// rasterizer threads once the commands are flushed); afterwards no texel is `written`.
void clearShadowTextures(ShadowGroupTextures& textures);

// Keeps group textures between renders (batch mode renders many similar scenes), up to a
// budget; textures are reused only for an exact match of key and layer count.
class ShadowTexturePool {
 public:
  // `madeZeroed`: the driver fills every texture it makes with zero bytes, as llvmpipe does
  // (its texture layout memsets the storage it allocates, Mesa's lp_texture.c). Zero is the
  // cleared depth, so a new depth-only texture needs no first clear: on llvmpipe that clear
  // wrote 24 MiB again for a 1024^2 cube, a third of a small scene's first shadow stage.
  explicit ShadowTexturePool(bool madeZeroed = false) : madeZeroed_(madeZeroed) {}

  ShadowGroupTextures take(const ShadowGroupPlan& plan);
  void give(ShadowGroupTextures&& textures);

 private:
  bool madeZeroed_;
  std::vector<ShadowGroupTextures> free_;
};

// One layer of a spot light's map or a directional cascade as distances (PlanarShadowMapDump):
// along the view axis (perspective) or from the near plane (orthographic), +inf where empty.
std::vector<float> readPlanarDistances(const ShadowGroupTextures& group,
                                       const LightShadowPlan& light, int layer, bool orthographic);

// Distances along each texel's ray of one light's cube in a cube map array (point lights).
CubeDistances readCubeDistances(const ShadowGroupTextures& group, const LightShadowPlan& light);

}  // namespace omnishadow
