#pragma once

#include <array>
#include <memory>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/shader_program.h"
#include "renderer/passes/gpu_scene.h"
#include "renderer/passes/shadow_textures.h"
#include "renderer/scene/light.h"
#include "renderer/view/caster_culling.h"
#include "renderer/view/shadow_plan.h"

namespace omnishadow {

// Where a light's translucent casters can tint its shadow: the bit per shadow layer (cube face,
// spot map, cascade) that some translucent caster's bounding sphere reaches, the texels each
// such layer's casters can cover, and which layers each caster (a scene draw) reaches.
struct TranslucentReach {
  int resolution = 0;  // of the light's shadow map, which `texels` counts in
  unsigned layers = 0u;
  std::vector<TexelRect> texels;       // per shadow layer of the light
  std::vector<unsigned> casterLayers;  // per scene draw, 0 for opaque ones
};

TranslucentReach translucentReach(const GpuScene& scene, const LightShadowPlan& plan,
                                  int resolution);

// A light's layers in the transmittance atlas: `layers` (bit per shadow layer) in order from
// atlas layer `first`.
struct AtlasLayers {
  int first = 0;
  unsigned layers = 0u;
  bool operator==(const AtlasLayers& other) const = default;
};

// What the lighting pass reads of the transmittance atlas (TransmittancePass::atlas()); both 0
// while no light has translucent shadows.
struct TransmittanceAtlas {
  GLuint layers = 0;
  GLuint rects = 0;
};

// Translucent shadows (README, "Translucent shadows"): after the shadow pass has drawn a
// light's opaque and cut-out casters, draws its translucent casters into the frame's
// transmittance atlas, one atlas layer per shadow layer they reach. Each layer holds
// (1, 1, 1, 0) where nothing is drawn; every fragment of a translucent caster in front of the
// opaque depth (depth-tested against the light's map, not written) multiplies RGB by what the
// surface lets through, front and back faces alike (no culling: each crossing counts once),
// and A keeps the largest, i.e. nearest, reversed depth of them (GL_MAX), so receivers in front
// of the glass stay untinted.
//
// Only the layers translucent casters reach take atlas layers (3 of 12 for the two point lights
// of WhackAMole), and each atlas layer holds only the texels its casters can cover (the layer's
// rectangle of `reach.texels`, from the atlas layer's corner): llvmpipe zeroes a new texture
// whole, 16 bytes a texel, which made full-size layers cost WhackAMole's first frame about 40
// ms. The atlas is as large as the largest rectangle. A layer whose rectangle starts at the map's
// corner is drawn in its atlas layer; any other is drawn in a map-sized scratch layer at the
// map's own coordinates and then copied, so that every caster is rasterized exactly as in the
// map (a viewport moved by the rectangle's corner would round window coordinates differently).
// The lighting pass finds each atlas layer's rectangle in a buffer texture (`rects`), and takes
// texels outside it, and shadow layers without atlas layers, as untinted.
class TransmittancePass {
 public:
  TransmittancePass();

  // Places the frame's lights in the atlas, in order (`reach` per light; empty for lights
  // without translucent shadows), growing it when it is too small. Returns each light's place;
  // `moved[i]` is true where the atlas does not hold what the light's last render() drew there
  // (a new place, a new atlas), so that a light whose shadow map is reused is drawn again.
  std::vector<AtlasLayers> place(const std::vector<TranslucentReach>& reach,
                                 std::vector<bool>& moved);

  // Draws the light's translucent casters into its atlas layers. `depth`: the group holding
  // the light's opaque shadow map.
  void render(const GpuScene& scene, const Light& light, const LightShadowPlan& plan,
              const ShadowGroupTextures& depth, const TranslucentReach& reach,
              const AtlasLayers& atlasLayers);

  // layers: GL_TEXTURE_2D_ARRAY, RGBA32F. rects: GL_TEXTURE_BUFFER, RGBA32I, per atlas layer
  // the rectangle (x0, y0, x1, y1) of its light's shadow layer that it holds from its corner.
  TransmittanceAtlas atlas() const { return {atlas_.get(), rectsTexture_.get()}; }

 private:
  // Where the layer's casters are drawn: its atlas layer, or the scratch layer.
  void attachTarget(const TexelRect& rect, int atlasLayer, int resolution);

  // The program for casters with or without volumes (bit 0) and diffuse transmission (bit 1),
  // made when first needed.
  const ShaderProgram& program(unsigned features);

  std::array<std::unique_ptr<ShaderProgram>, 4> programs_;
  gl::Framebuffer framebuffer_;
  gl::Texture atlas_;
  int width_ = 0, height_ = 0, layers_ = 0;
  gl::Buffer rectsBuffer_;
  gl::Texture rectsTexture_;
  // A map-sized GL_TEXTURE_2D, made for the first rectangle off the map's corner.
  gl::Texture scratch_;
  int scratchResolution_ = 0;
  // Per light of the last place(): where it was put.
  std::vector<AtlasLayers> placed_;
};

}  // namespace omnishadow
