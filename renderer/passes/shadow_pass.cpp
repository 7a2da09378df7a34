#include "renderer/passes/shadow_pass.h"

#include <algorithm>
#include <cstdint>

#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/passes/shadow_layer_binding.h"
#include "renderer/passes/vsm_filter.h"
#include "renderer/scene/translucency.h"
#include "renderer/view/caster_culling.h"
#include "renderer/view/shadow_draws.h"

namespace omnishadow {

ShadowPassStrategy resolveShadowPassStrategy(ShadowPassStrategy requested,
                                             const std::string& glRenderer) {
  if (requested != ShadowPassStrategy::Auto) return requested;
  // Measured with scripts/bench-shadows.sh (docs/performance.md), 250k triangles, 4 point
  // lights at 1024^2, llvmpipe on 2 cores (9853f53): six 305 ms, instanced 336 ms, geometry
  // 677 ms (medians of 9 rounds). llvmpipe runs the geometry shader on the thread that also does
  // all vertex work and setup, while per-face passes keep that thread light and let the
  // rasterizer threads work. On an NVIDIA H100 (scripts/bench-gpu.sh, three runs of 5 rounds,
  // steady pass): six 16.0-17.8 ms, instanced 15.0-16.9, geometry 25.0-27.5; instanced was
  // ahead of six by 3-8% in 14 rounds of 15. On an NVIDIA H200 at 7249b74 (two runs of 5
  // rounds): six 7.7-9.1 ms, instanced 7.6-8.7, geometry 17.9-19.2; neither of six and
  // instanced ahead in every round. Not chosen by driver: no GPU showed a margin worth a rule.
  (void)glRenderer;
  return ShadowPassStrategy::Six;
}

SceneCasters describeCasters(const GpuScene& scene) {
  SceneCasters out;
  out.casters.reserve(scene.draws().size());
  out.geometry.reserve(scene.draws().size());
  for (const GpuDraw& draw : scene.draws()) {
    const Material& material = scene.materials()[draw.material].desc;
    const GpuMeshRange& range = scene.meshes()[draw.mesh];
    // Blended surfaces cast cut-out shadows (where at least half opaque) for lights without
    // translucent shadows.
    out.casters.push_back({draw.boundsCenter, draw.boundsRadius,
                           material.alphaMode != AlphaMode::Opaque, range.closed,
                           material.doubleSided, draw.mirrored, draw.plane});
    out.geometry.push_back({static_cast<std::uint32_t>(range.indexCount),
                            static_cast<std::uint32_t>(range.firstIndex), range.baseVertex,
                            draw.casterFirstIndex});
    if (isTranslucentCaster(material)) out.translucent.push_back(out.casters.size() - 1);
  }
  out.reach.emplace(out.casters);
  return out;
}

ShadowPass::ShadowPass() : framebuffer_(gl::createFramebuffer()) {}
ShadowPass::~ShadowPass() = default;

const ShaderProgram& ShadowPass::program(ShadowPassStrategy strategy, bool masked, bool moments,
                                         bool worldPositions) {
  const int key = static_cast<int>(strategy) * 8 + (worldPositions ? 4 : 0) + (masked ? 2 : 0) +
                  (moments ? 1 : 0);
  auto& slot = programs_[key];
  if (!slot) {
    std::vector<std::string> defines;
    if (masked) defines.emplace_back("ALPHA_MASK");
    if (moments) defines.emplace_back("MOMENTS");
    if (worldPositions) defines.emplace_back("WORLD_POSITIONS");
    std::string geometry;
    if (strategy == ShadowPassStrategy::Instanced) defines.emplace_back("LAYER_FROM_INSTANCE");
    if (strategy == ShadowPassStrategy::Geometry) {
      defines.emplace_back("GEOMETRY_LAYERS");
      geometry = "shadow_depth.geom";
    }
    slot = std::make_unique<ShaderProgram>("shadow_depth.vert", "shadow_depth.frag",
                                           contract::withShaderContract(defines), geometry);
  }
  return *slot;
}

namespace {

ShadowLayering layeringOf(ShadowPassStrategy strategy) {
  switch (strategy) {
    case ShadowPassStrategy::Instanced:
      return ShadowLayering::Instanced;
    case ShadowPassStrategy::Geometry:
      return ShadowLayering::Geometry;
    default:
      return ShadowLayering::PerView;
  }
}

// Per layer of the light: the texels its casters (those culling keeps for the layer) may
// cover, from their bounding spheres.
std::vector<TexelRect> casterTexels(const std::vector<ShadowCaster>& casters,
                                    const CasterCulling& culling, const LightShadowPlan& plan,
                                    int resolution) {
  std::vector<TexelRect> texels(static_cast<std::size_t>(plan.layerCount));
  // Layers already whole cannot grow: their casters need no projection.
  unsigned open = plan.layerCount >= 32 ? ~0u : (1u << plan.layerCount) - 1u;
  for (std::size_t c = 0; c < casters.size() && open != 0u; ++c) {
    const unsigned views = culling.viewMask[c] & open;
    if (views == 0u) continue;
    uniteCasterTexels(plan, views, casters[c].center, casters[c].radius, resolution, texels);
    for (int layer = 0; layer < plan.layerCount; ++layer)
      if ((views >> layer & 1u) != 0u &&
          texels[static_cast<std::size_t>(layer)] == TexelRect::whole(resolution))
        open &= ~(1u << layer);
  }
  return texels;
}

gl::CullState cullStateOf(CullBucket bucket, CullFace cullFace) {
  gl::CullState cull;
  cull.enabled = bucket != CullBucket::None;
  cull.face = cullFace == CullFace::Front ? GL_FRONT : GL_BACK;
  cull.front = bucket == CullBucket::Cw ? GL_CW : GL_CCW;
  return cull;
}

}  // namespace

// One light's pass: what its helpers share.
struct ShadowPass::LightPass {
  const GpuScene& scene;
  const SceneVertexArrays& arrays;
  const Light& light;
  const LightShadowPlan& plan;
  ShadowPassStrategy strategy;
  bool moments;
  ShadowLayerBinding& layers;
};

int ShadowPass::render(const GpuScene& scene, const SceneVertexArrays& arrays,
                       const SceneCasters& sceneCasters, const Light& light,
                       const LightShadowPlan& plan, ShadowGroupTextures& target,
                       ShadowPassStrategy strategy, bool everyCaster) {
  const bool cube = target.key.layout == ShadowLayout::Cube;
  if (!cube || strategy == ShadowPassStrategy::Auto) strategy = ShadowPassStrategy::Six;
  const ShadowLayering layering = layeringOf(strategy);
  const bool moments = target.key.moments;

  const std::vector<ShadowCaster>& casters = sceneCasters.casters;
  // Variance maps are blurred: a left-out floor would change its neighbours' moments.
  CasterCulling culling = cullCasters(casters, shadowCullingLight(light, plan, cube),
                                      everyCaster || moments ? Bounds{} : scene.receiverBounds(),
                                      sceneCasters.reach ? &*sceneCasters.reach : nullptr);

  // With translucent shadows, translucent casters tint the light in the transmittance pass
  // (transmittance_pass.h) instead of blocking it here.
  if (castsTranslucentShadows(light))
    for (const std::size_t c : sceneCasters.translucent) culling.viewMask[c] = 0;
  const ShadowDrawList draws = buildShadowDraws(casters, sceneCasters.geometry, culling,
                                                plan.layerCount, layering, !moments);
  commands_.upload(draws.commands);
  drawObjects_.upload(draws.objects);

  const GLuint fb = framebuffer_.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  rasterState(light.shadow, moments, target.key.resolution).apply();
  glNamedFramebufferDrawBuffer(fb, moments ? GL_COLOR_ATTACHMENT0 : GL_NONE);
  glNamedFramebufferReadBuffer(fb, GL_NONE);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kModelsBinding, scene.modelBuffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kDrawObjectsBinding, drawObjects_.get());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_.get());

  ShadowLayerBinding layers(fb, target, plan.firstLayer, plan.layerCount,
                            casterTexels(casters, culling, plan, target.key.resolution),
                            moments ? VsmFilter::spread(light.shadow.filterRadius) : 0);
  if (layering != ShadowLayering::PerView) layers.bind(ShadowLayerBinding::kAllLayers);
  const LightPass pass{scene, arrays, light, plan, strategy, moments, layers};
  drawOpaque(pass, draws);
  drawMasked(pass, draws, culling);
  layers.clearUnbound();  // views nothing was drawn into still hold another frame's depths

  // The next pass may clear before it sets its own state, and clears obey the write masks.
  gl::RasterState::restoreDefaults();
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  layers.detach();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the shadow pass of light \"" + light.name + "\"");
  return culling.flatLeftOut;
}

gl::RasterState ShadowPass::rasterState(const ShadowSettings& settings, bool moments,
                                        int resolution) {
  gl::RasterState state;  // depth test and writes on, reversed depth
  state.viewport = {0, 0, resolution, resolution};
  state.color.rgba = {moments, moments, false, false};
  if (settings.polygonOffsetFactor != 0.0f || settings.polygonOffsetUnits != 0.0f) {
    // Reversed depth: pushing casters away from the light means smaller depth values.
    state.offset = {true, -settings.polygonOffsetFactor, -settings.polygonOffsetUnits};
  }
  return state;
}

void ShadowPass::prepare(const LightPass& pass, const ShaderProgram& p, int view) {
  p.use();
  p.set("uViewProjections", pass.plan.viewProjection.data(), pass.plan.layerCount);
  p.set("uView", std::max(view, 0));
  if (pass.moments) {
    p.set("uLightPosition", pass.light.position);
    p.set("uMomentScale", 1.0f / pass.plan.far);
    p.set("uMomentFromDepth", pass.light.type == LightType::Directional ? 1 : 0);
  }
}

// One multi-draw per (view, culling state, vertex source).
void ShadowPass::drawOpaque(const LightPass& pass, const ShadowDrawList& draws) {
  for (const OpaqueShadowBatch& batch : draws.opaque) {
    pass.layers.bind(batch.view);
    const ShaderProgram& opaque = program(pass.strategy, false, pass.moments, batch.world);
    glBindVertexArray(batch.world ? pass.arrays.casters.get() : pass.arrays.scene.get());
    prepare(pass, opaque, batch.view);
    opaque.set("uObject", -1);
    opaque.set("uDrawBase", batch.first);
    cullStateOf(batch.bucket, pass.light.shadow.cullFace).apply();
    glMultiDrawElementsIndirect(
        GL_TRIANGLES, GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(static_cast<std::uintptr_t>(batch.first) *
                                      sizeof(IndirectDrawCommand)),
        batch.count, 0);
  }
}

// Alpha-tested casters one by one, each with its own texture.
void ShadowPass::drawMasked(const LightPass& pass, const ShadowDrawList& draws,
                            const CasterCulling& culling) {
  glBindVertexArray(pass.arrays.scene.get());
  const ShaderProgram& masked = program(pass.strategy, true, pass.moments, false);
  int preparedView = ShadowLayerBinding::kAllLayers - 1;
  for (const MaskedShadowDraw& draw : draws.masked) {
    if (draw.view != preparedView) {
      pass.layers.bind(draw.view);
      prepare(pass, masked, draw.view);
      preparedView = draw.view;
    }
    const GpuDraw& gpuDraw = pass.scene.draws()[static_cast<std::size_t>(draw.caster)];
    const GpuMaterial& material = pass.scene.materials()[gpuDraw.material];
    masked.set("uObject", draw.caster);
    masked.set("uBaseColorFactor", material.desc.baseColorFactor);
    masked.set("uHasBaseColorTexture", material.baseColor != 0 ? 1 : 0);
    masked.set("uBaseColorTexCoord", material.desc.baseColorTexture.texCoord);
    masked.set("uBaseColorUvTransform", material.desc.baseColorTexture.uvTransform);
    masked.set("uAlphaCutoff",
               material.desc.alphaMode == AlphaMode::Mask ? material.desc.alphaCutoff : 0.5f);
    glBindTextureUnit(contract::kBaseColorUnit, material.baseColor);
    glBindSampler(0, material.baseColorSampler);
    cullStateOf(culling.bucket[static_cast<std::size_t>(draw.caster)], pass.light.shadow.cullFace)
        .apply();
    const GpuMeshRange& range = pass.scene.meshes()[gpuDraw.mesh];
    const void* offset =
        reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4);
    forEachFaceRun(draw.instances, pass.plan.layerCount, [&](int first, int count) {
      glDrawElementsInstancedBaseVertexBaseInstance(GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT,
                                                    offset, count, range.baseVertex,
                                                    static_cast<GLuint>(first));
    });
  }
}

}  // namespace omnishadow
