#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/raster_state.h"
#include "renderer/gl/shader_program.h"
#include "renderer/passes/gpu_scene.h"
#include "renderer/passes/shadow_textures.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/light.h"
#include "renderer/view/caster_reach_grid.h"
#include "renderer/view/shadow_draws.h"

namespace omnishadow {

// What `auto` means on a GL renderer (its GL_RENDERER string).
ShadowPassStrategy resolveShadowPassStrategy(ShadowPassStrategy requested,
                                             const std::string& glRenderer);

// What culling and batching know of a scene's draws, in draw order: the same for every light,
// so described once per frame rather than once per light.
struct SceneCasters {
  std::vector<ShadowCaster> casters;
  std::vector<CasterGeometry> geometry;
  // The casters drawn with a translucent material (isTranslucentCaster), ascending: lights
  // with translucent shadows leave them to the transmittance pass. Found once per frame, not
  // per light: a material lookup per caster and light cost 256 lights on 2006 casters 9 ms.
  std::vector<std::size_t> translucent;
  std::optional<CasterReachGrid> reach;  // of `casters`
};
SceneCasters describeCasters(const GpuScene& scene);

// Renders depth (and vsm moments) of one light's layers. Spot lights and directional cascades
// are always drawn one layer per pass; the strategy applies to point lights. Opaque casters
// are drawn with glMultiDrawElementsIndirect; alpha-tested ones one by one with their texture.
class ShadowPass {
 public:
  ShadowPass();
  ~ShadowPass();

  // What render() works out on the CPU before its GL calls: the light's casters culled, its
  // draw lists and the texels they may cover per layer.
  struct LightDraws {
    CasterCulling culling;
    ShadowDrawList draws;
    std::vector<TexelRect> texels;  // per layer (casterTexels)
  };
  // render()'s LightDraws for these arguments; touches no GL state, so any thread may make
  // them, many lights at once, ahead of the GL calls (Renderer: 16 lights or more in one
  // context).
  static LightDraws planDraws(const GpuScene& scene, const SceneCasters& casters,
                              const Light& light, const LightShadowPlan& plan,
                              const ShadowGroupTextures& target, ShadowPassStrategy strategy,
                              bool everyCaster);

  // Draws the light's layers of `target` and updates their `written` texels. Flat casters
  // that shadow no receiver (shadowsNoReceiver) are left out unless `everyCaster`: maps that
  // are read back (depth dumps, the depth view) hold the whole scene as the light sees it.
  // Returns how many flat casters it left out. `arrays`: the scene's vertex arrays as the
  // current context knows them (GpuScene::vertexArrays() in the context that made the scene).
  // `planned`: planDraws()'s result for the same arguments, or null to work it out here.
  int render(const GpuScene& scene, const SceneVertexArrays& arrays, const SceneCasters& casters,
             const Light& light, const LightShadowPlan& plan, ShadowGroupTextures& target,
             ShadowPassStrategy strategy, bool everyCaster, const LightDraws* planned = nullptr);

  // ShadowPassStrategy::Batched: draws the maps of several point lights of one group in one
  // pass, the group's whole texture attached once, as render() would with Instanced. The
  // lights must share `target` (cube layout, no moments) and their shadow's polygon offset and
  // cull face. Layers are cleared where they may hold something (as ShadowLayerBinding does):
  // with `wholeTexture` (these are all the lights whose maps the texture holds this frame) by
  // one layered clear, else light by light with glClearTexSubImage, since a layered clear would
  // clear the other lights' maps too. Returns each light's count of flat casters left out.
  struct BatchedLight {
    const Light* light = nullptr;
    const LightShadowPlan* plan = nullptr;
  };
  std::vector<int> renderBatched(const GpuScene& scene, const SceneVertexArrays& arrays,
                                 const SceneCasters& casters,
                                 const std::vector<BatchedLight>& lights,
                                 ShadowGroupTextures& target, bool everyCaster, bool wholeTexture);

 private:
  struct LightPass;
  static LightDraws lightDraws(const GpuScene& scene, const SceneCasters& casters,
                               const Light& light, const LightShadowPlan& plan,
                               ShadowLayering layering, bool cube, bool moments, bool everyCaster);
  const ShaderProgram& program(ShadowPassStrategy strategy, bool masked, bool moments,
                               bool worldPositions);
  static gl::RasterState rasterState(const ShadowSettings& settings, bool moments, int resolution);
  static void prepare(const LightPass& pass, const ShaderProgram& p, int view);
  void drawOpaque(const LightPass& pass, const ShadowDrawList& draws);
  void drawMasked(const LightPass& pass, const ShadowDrawList& draws, const CasterCulling& culling);

  std::map<int, std::unique_ptr<ShaderProgram>> programs_;
  gl::Framebuffer framebuffer_;
  gl::StreamBuffer commands_, drawObjects_;
  gl::StreamBuffer layerViewProjections_;  // renderBatched's, per layer of its texture
};

}  // namespace omnishadow
