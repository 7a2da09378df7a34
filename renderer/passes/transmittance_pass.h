#pragma once

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/shader_program.h"
#include "renderer/passes/gpu_scene.h"
#include "renderer/passes/shadow_textures.h"
#include "renderer/scene/light.h"
#include "renderer/view/shadow_plan.h"

namespace omnishadow {

// Translucent shadows (README, "Translucent shadows"): after the shadow pass has drawn a
// light's opaque and cut-out casters, draws its translucent casters (translucency.h) into the
// group's transmittance layers, one layer (cube face, spot map, cascade) at a time. Each layer
// is cleared to (1, 1, 1, 0); every fragment of a translucent caster in front of the opaque
// depth (depth-tested, not written) multiplies RGB by what the surface lets through, front and
// back faces alike (no culling: each crossing counts once), and A keeps the largest, i.e.
// nearest, reversed depth of them (GL_MAX), so receivers in front of the glass stay untinted.
// Layers whose frustum no translucent caster's bounding sphere touches are skipped and marked
// untinted in ShadowGroupTextures::tintedLayers; the lighting pass takes their transmittance
// as 1 (what a cleared layer holds) without reading them.
class TransmittancePass {
 public:
  TransmittancePass();

  // `target` must have its transmittance layers (ensureTransmittance()); sets its tintedLayers
  // of the light's layers.
  void render(const GpuScene& scene, const Light& light, const LightShadowPlan& plan,
              ShadowGroupTextures& target);

 private:
  ShaderProgram program_;
  gl::Framebuffer framebuffer_;
};

}  // namespace omnishadow
