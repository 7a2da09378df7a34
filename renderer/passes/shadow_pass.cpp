#include "renderer/passes/shadow_pass.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>

#include "renderer/core/in_parts.h"
#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/passes/shadow_layer_binding.h"
#include "renderer/passes/texel_scissor.h"
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
  // instanced ahead in every round. `batched` (one pass for all point lights), on an H200 with
  // 256 lights on 1M triangles (eab6c48, 3 rounds): six 74.0 ms, instanced 72.3, batched 86.0
  // at 512^2; 209.3, 206.9 and 229.4 at 1024^2: it spares the driver's per-light submission,
  // but the GPU's own work is then the bound, and larger. Not chosen by driver: no GPU showed a
  // margin worth a rule.
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
    // Opaque copies in the caster stream are drawn from it, welded where that closes them.
    const bool closed = draw.casterFirstIndex >= 0 ? range.closedInStream : range.closed;
    // Blended surfaces cast cut-out shadows (where at least half opaque) for lights without
    // translucent shadows.
    out.casters.push_back({draw.boundsCenter, draw.boundsRadius,
                           material.alphaMode != AlphaMode::Opaque, closed, material.doubleSided,
                           draw.mirrored, draw.plane, draw.repeatedLater});
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
    if (strategy == ShadowPassStrategy::Instanced || strategy == ShadowPassStrategy::Batched)
      defines.emplace_back("LAYER_FROM_INSTANCE");
    if (strategy == ShadowPassStrategy::Batched) defines.emplace_back("LAYER_MATRICES");
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
    case ShadowPassStrategy::Batched:
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

// One alpha-tested caster with its material's texture: an instanced draw per run of its
// faces, the instances starting at `firstLayer` (0 where a view of the light's own layers is
// attached).
void drawMaskedCaster(const GpuScene& scene, const ShaderProgram& masked,
                      const MaskedShadowDraw& draw, CullBucket bucket, CullFace cullFace,
                      int layerCount, int firstLayer) {
  const GpuDraw& gpuDraw = scene.draws()[static_cast<std::size_t>(draw.caster)];
  const GpuMaterial& material = scene.materials()[gpuDraw.material];
  masked.set("uObject", draw.caster);
  masked.set("uBaseColorFactor", material.desc.baseColorFactor);
  masked.set("uHasBaseColorTexture", material.baseColor != 0 ? 1 : 0);
  masked.set("uBaseColorTexCoord", material.desc.baseColorTexture.texCoord);
  masked.set("uBaseColorUvTransform", material.desc.baseColorTexture.uvTransform);
  masked.set("uAlphaCutoff",
             material.desc.alphaMode == AlphaMode::Mask ? material.desc.alphaCutoff : 0.5f);
  glBindTextureUnit(contract::kBaseColorUnit, material.baseColor);
  glBindSampler(0, material.baseColorSampler);
  cullStateOf(bucket, cullFace).apply();
  const GpuMeshRange& range = scene.meshes()[gpuDraw.mesh];
  const void* offset =
      reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4);
  forEachFaceRun(draw.instances, layerCount, [&](int first, int count) {
    glDrawElementsInstancedBaseVertexBaseInstance(GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT,
                                                  offset, count, range.baseVertex,
                                                  static_cast<GLuint>(firstLayer + first));
  });
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

ShadowPass::LightDraws ShadowPass::lightDraws(const GpuScene& scene,
                                              const SceneCasters& sceneCasters, const Light& light,
                                              const LightShadowPlan& plan, ShadowLayering layering,
                                              bool cube, bool moments, bool everyCaster) {
  const std::vector<ShadowCaster>& casters = sceneCasters.casters;
  // Variance maps are blurred: a left-out floor would change its neighbours' moments.
  CasterCulling culling = cullCasters(casters, shadowCullingLight(light, plan, cube),
                                      everyCaster || moments ? Bounds{} : scene.receiverBounds(),
                                      sceneCasters.reach ? &*sceneCasters.reach : nullptr);

  // With translucent shadows, translucent casters tint the light in the transmittance pass
  // (transmittance_pass.h) instead of blocking it here.
  if (castsTranslucentShadows(light))
    for (const std::size_t c : sceneCasters.translucent) culling.viewMask[c] = 0;
  ShadowDrawList draws = buildShadowDraws(casters, sceneCasters.geometry, culling, plan.layerCount,
                                          layering, !moments);
  return {std::move(culling), std::move(draws), {}};
}

namespace {

// The strategy render() draws a light's layers of `target` with.
ShadowPassStrategy drawnStrategy(ShadowPassStrategy strategy, const ShadowGroupTextures& target) {
  // A light drawn alone under Batched (renderBatched takes the others) is drawn as by Six.
  if (target.key.layout != ShadowLayout::Cube || strategy == ShadowPassStrategy::Auto ||
      strategy == ShadowPassStrategy::Batched)
    return ShadowPassStrategy::Six;
  return strategy;
}

}  // namespace

ShadowPass::LightDraws ShadowPass::planDraws(const GpuScene& scene,
                                             const SceneCasters& sceneCasters, const Light& light,
                                             const LightShadowPlan& plan,
                                             const ShadowGroupTextures& target,
                                             ShadowPassStrategy strategy, bool everyCaster) {
  LightDraws planned =
      lightDraws(scene, sceneCasters, light, plan, layeringOf(drawnStrategy(strategy, target)),
                 target.key.layout == ShadowLayout::Cube, target.key.moments, everyCaster);
  planned.texels = casterTexels(sceneCasters.casters, planned.culling, plan, target.key.resolution);
  return planned;
}

int ShadowPass::render(const GpuScene& scene, const SceneVertexArrays& arrays,
                       const SceneCasters& sceneCasters, const Light& light,
                       const LightShadowPlan& plan, ShadowGroupTextures& target,
                       ShadowPassStrategy strategy, bool everyCaster, const LightDraws* planned) {
  strategy = drawnStrategy(strategy, target);
  const ShadowLayering layering = layeringOf(strategy);
  const bool moments = target.key.moments;

  std::optional<LightDraws> here;
  if (!planned)
    planned =
        &here.emplace(planDraws(scene, sceneCasters, light, plan, target, strategy, everyCaster));
  const CasterCulling& culling = planned->culling;
  const ShadowDrawList& draws = planned->draws;
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

  ShadowLayerBinding layers(fb, target, plan.firstLayer, plan.layerCount, planned->texels,
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

std::vector<int> ShadowPass::renderBatched(const GpuScene& scene, const SceneVertexArrays& arrays,
                                           const SceneCasters& sceneCasters,
                                           const std::vector<BatchedLight>& lights,
                                           ShadowGroupTextures& target, bool everyCaster,
                                           bool wholeTexture) {
  std::vector<int> flatLeftOut;
  if (lights.empty()) return flatLeftOut;
  // Each light's culling and draws are CPU work of its own, which the driver waits for: from
  // 16 lights on, spread over the machine's threads (a GPU's host has cores to spare). Drawn
  // as Instanced draws them (the target is a cube map array without moments).
  std::vector<LightDraws> perLight(lights.size());
  const auto planLights = [&](std::size_t /*part*/, std::size_t first, std::size_t end) {
    for (std::size_t i = first; i < end; ++i)
      perLight[i] = planDraws(scene, sceneCasters, *lights[i].light, *lights[i].plan, target,
                              ShadowPassStrategy::Instanced, everyCaster);
  };
  inParts(lights.size(), partsFor(lights.size()), planLights);
  for (const LightDraws& draws : perLight) flatLeftOut.push_back(draws.culling.flatLeftOut);

  // The shader reads the layers' view-projections from a uniform block: a window of
  // kMaxUniformViewProjections layers from a base the block's binding offset must allow.
  // Lights whose layers fit one window are drawn together.
  GLint alignment = 256;
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &alignment);
  // The fewest layers whose 64 bytes each make a multiple of the alignment.
  const int alignmentBytes = std::max(1, static_cast<int>(alignment));
  const int layerAlignment = alignmentBytes / std::gcd(alignmentBytes, 64);
  constexpr int kWindow = contract::kMaxUniformViewProjections;
  struct Window {
    int base = 0;
    std::size_t firstLight = 0, endLight = 0;
    std::size_t firstBatch = 0, endBatch = 0;  // in merged.opaque
  };
  std::vector<Window> windows;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const LightShadowPlan& plan = *lights[i].plan;
    if (!windows.empty() && plan.firstLayer >= windows.back().base &&
        plan.firstLayer + plan.layerCount <= windows.back().base + kWindow) {
      windows.back().endLight = i + 1;
      continue;
    }
    const int base = plan.firstLayer / layerAlignment * layerAlignment;
    windows.push_back({base, i, i + 1, 0, 0});
  }

  // Per window, one batch per (cull state, vertex source) for all its lights: their commands
  // one after the other, each instance range moved to the light's layers of the texture. The
  // layers are the lights' own, so the order between lights changes no texel.
  ShadowDrawList merged;
  for (Window& window : windows) {
    window.firstBatch = merged.opaque.size();
    for (int bucket = 0; bucket < kCullBucketCount; ++bucket)
      for (const bool world : {true, false}) {
        const int first = static_cast<int>(merged.commands.size());
        for (std::size_t i = window.firstLight; i < window.endLight; ++i) {
          const ShadowDrawList& draws = perLight[i].draws;
          for (const OpaqueShadowBatch& batch : draws.opaque) {
            if (batch.bucket != static_cast<CullBucket>(bucket) || batch.world != world) continue;
            for (int c = batch.first; c < batch.first + batch.count; ++c) {
              IndirectDrawCommand command = draws.commands[static_cast<std::size_t>(c)];
              command.baseInstance += static_cast<std::uint32_t>(lights[i].plan->firstLayer);
              merged.commands.push_back(command);
              merged.objects.push_back(draws.objects[static_cast<std::size_t>(c)]);
            }
          }
        }
        const int count = static_cast<int>(merged.commands.size()) - first;
        if (count > 0)
          merged.opaque.push_back({static_cast<CullBucket>(bucket), -1, world, first, count});
      }
    window.endBatch = merged.opaque.size();
  }
  commands_.upload(merged.commands);
  drawObjects_.upload(merged.objects);
  // Every layer's matrix, and a window's worth beyond the last: a bound range is always as
  // large as the block.
  std::vector<glm::mat4> layerMatrices(static_cast<std::size_t>(target.layers + kWindow),
                                       glm::mat4(0.0f));
  for (const BatchedLight& l : lights)
    for (int layer = 0; layer < l.plan->layerCount; ++layer)
      layerMatrices[static_cast<std::size_t>(l.plan->firstLayer + layer)] =
          l.plan->viewProjection[static_cast<std::size_t>(layer)];
  layerViewProjections_.upload(layerMatrices);

  const GLuint fb = framebuffer_.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  const ShadowSettings& settings = lights.front().light->shadow;
  // Before the clears, which obey its masks.
  rasterState(settings, false, target.key.resolution).apply();
  glNamedFramebufferDrawBuffer(fb, GL_NONE);
  glNamedFramebufferReadBuffer(fb, GL_NONE);
  glNamedFramebufferTexture(fb, GL_DEPTH_ATTACHMENT, target.depth.get(), 0);  // every layer
  glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, 0, 0);

  // The layers are cleared where they may hold something, then marked with what this pass may
  // draw there (as ShadowLayerBinding::bind(kAllLayers) does). When the pass draws every light
  // of the texture, one layered clear of the framebuffer does it for all layers (llvmpipe then
  // clears in its rasterizer threads); else each light's layers are cleared through the
  // texture, since a layered clear would also clear the maps of other lights.
  const auto written = [&](int layer) -> TexelRect& {
    return target.written[static_cast<std::size_t>(layer)];
  };
  if (wholeTexture) {
    TexelRect anyWritten;
    for (int layer = 0; layer < target.layers; ++layer)
      anyWritten = anyWritten.united(written(layer));
    if (!anyWritten.empty()) {
      scissorTo(anyWritten);
      glClearNamedFramebufferfv(fb, GL_DEPTH, 0, &kClearedDepth);
      gl::Scissor{}.apply();
    }
    for (int layer = 0; layer < target.layers; ++layer) written(layer) = TexelRect{};
  }
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const LightShadowPlan& plan = *lights[i].plan;
    if (!wholeTexture) {
      TexelRect anyWritten;
      for (int layer = 0; layer < plan.layerCount; ++layer)
        anyWritten = anyWritten.united(written(plan.firstLayer + layer));
      if (!anyWritten.empty())
        glClearTexSubImage(target.depth.get(), 0, anyWritten.x0, anyWritten.y0, plan.firstLayer,
                           anyWritten.x1 - anyWritten.x0, anyWritten.y1 - anyWritten.y0,
                           plan.layerCount, GL_DEPTH_COMPONENT, GL_FLOAT, &kClearedDepth);
    }
    for (int layer = 0; layer < plan.layerCount; ++layer)
      written(plan.firstLayer + layer) = perLight[i].texels[static_cast<std::size_t>(layer)];
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kModelsBinding, scene.modelBuffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kDrawObjectsBinding, drawObjects_.get());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_.get());

  for (const Window& window : windows) {
    glBindBufferRange(GL_UNIFORM_BUFFER, contract::kLayerViewProjectionsUniformBinding,
                      layerViewProjections_.get(),
                      static_cast<GLintptr>(window.base) * GLintptr{64},
                      GLsizeiptr{kWindow} * GLsizeiptr{64});
    for (std::size_t b = window.firstBatch; b < window.endBatch; ++b) {
      const OpaqueShadowBatch& batch = merged.opaque[b];
      const ShaderProgram& opaque = program(ShadowPassStrategy::Batched, false, false, batch.world);
      glBindVertexArray(batch.world ? arrays.casters.get() : arrays.scene.get());
      opaque.use();
      opaque.set("uLayerBase", window.base);
      opaque.set("uObject", -1);
      opaque.set("uDrawBase", batch.first);
      cullStateOf(batch.bucket, settings.cullFace).apply();
      glMultiDrawElementsIndirect(
          GL_TRIANGLES, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(batch.first) *
                                        sizeof(IndirectDrawCommand)),
          batch.count, 0);
    }

    // Alpha-tested casters one by one, light by light, each with its own texture.
    glBindVertexArray(arrays.scene.get());
    const ShaderProgram& masked = program(ShadowPassStrategy::Batched, true, false, false);
    masked.use();
    masked.set("uLayerBase", window.base);
    for (std::size_t i = window.firstLight; i < window.endLight; ++i) {
      const LightShadowPlan& plan = *lights[i].plan;
      for (const MaskedShadowDraw& draw : perLight[i].draws.masked) {
        drawMaskedCaster(scene, masked, draw,
                         perLight[i].culling.bucket[static_cast<std::size_t>(draw.caster)],
                         settings.cullFace, plan.layerCount, plan.firstLayer);
      }
    }
  }

  gl::RasterState::restoreDefaults();
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, contract::kLayerViewProjectionsUniformBinding, 0);
  glNamedFramebufferTexture(fb, GL_DEPTH_ATTACHMENT, 0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the batched shadow pass of " + std::to_string(lights.size()) + " lights");
  return flatLeftOut;
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
    drawMaskedCaster(pass.scene, masked, draw,
                     culling.bucket[static_cast<std::size_t>(draw.caster)],
                     pass.light.shadow.cullFace, pass.plan.layerCount, 0);
  }
}

}  // namespace omnishadow
