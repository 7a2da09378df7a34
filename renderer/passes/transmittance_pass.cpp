#include "renderer/passes/transmittance_pass.h"

#include <cstdint>

#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/scene/translucency.h"
#include "renderer/view/caster_culling.h"

namespace omnishadow {

TransmittancePass::TransmittancePass()
    : program_("shadow_depth.vert", "shadow_transmittance.frag",
               contract::withShaderContract({"TRANSMITTANCE"})),
      framebuffer_(gl::createFramebuffer()) {}

namespace {

void scissorTo(const TexelRect& rect) {
  gl::Scissor{true, rect.x0, rect.y0, rect.x1 - rect.x0, rect.y1 - rect.y0}.apply();
}

}  // namespace

void TransmittancePass::render(const GpuScene& scene, const Light& light,
                               const LightShadowPlan& plan, ShadowGroupTextures& target) {
  // Which layers each translucent caster can reach.
  std::vector<ViewFrustum> views;
  for (int layer = 0; layer < plan.layerCount; ++layer)
    views.emplace_back(plan.viewProjection[layer]);
  std::vector<unsigned> casterLayers(scene.draws().size(), 0u);
  std::vector<TexelRect> drawn(static_cast<std::size_t>(plan.layerCount));
  const int n = target.key.resolution;
  unsigned tinted = 0u;
  for (std::size_t index = 0; index < scene.draws().size(); ++index) {
    const GpuDraw& draw = scene.draws()[index];
    if (!isTranslucentCaster(scene.materials()[draw.material].desc)) continue;
    unsigned& layers = casterLayers[index];
    layers = casterViewMask(views, draw.boundsCenter, draw.boundsRadius);
    for (int layer = 0; layer < plan.layerCount; ++layer) {
      if ((layers >> layer & 1u) == 0) continue;
      const TexelRect rect =
          sphereTexelRect(plan.viewProjection[layer], draw.boundsCenter, draw.boundsRadius, n);
      if (rect.empty()) layers &= ~(1u << layer);
      drawn[layer] = drawn[layer].united(rect);
    }
    tinted |= layers;
  }
  target.tintedLayers.resize(target.layers, false);
  for (int layer = 0; layer < plan.layerCount; ++layer)
    target.tintedLayers[plan.firstLayer + layer] = (tinted >> layer & 1u) != 0;
  if (tinted == 0u) return;

  const GLuint fb = framebuffer_.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  glNamedFramebufferDrawBuffer(fb, GL_COLOR_ATTACHMENT0);
  glNamedFramebufferReadBuffer(fb, GL_NONE);
  gl::RasterState state;
  state.viewport = {0, 0, target.key.resolution, target.key.resolution};
  state.depth.write = false;  // tested against the opaque casters' depth (reversed: GL_GREATER)
  state.blend.buffers = 1u;
  state.blend.sourceColor = GL_ZERO;
  state.blend.destinationColor = GL_SRC_COLOR;
  state.blend.sourceAlpha = state.blend.destinationAlpha = GL_ONE;
  state.blend.alphaEquation = GL_MAX;
  state.apply();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kModelsBinding, scene.modelBuffer());
  // Single draws (uObject) never read DrawObjects, but the vertex stage declares it: any buffer
  // keeps the binding valid.
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kDrawObjectsBinding, scene.modelBuffer());
  glBindVertexArray(scene.vertexArray());
  program_.use();
  program_.set("uViewProjections", plan.viewProjection.data(), plan.layerCount);
  program_.set("uDrawBase", 0);

  const float clear[4] = {1.0f, 1.0f, 1.0f, 0.0f};
  for (int layer = 0; layer < plan.layerCount; ++layer) {
    if ((tinted >> layer & 1u) == 0) continue;
    glNamedFramebufferTextureLayer(fb, GL_DEPTH_ATTACHMENT, target.depth.get(), 0,
                                   plan.firstLayer + layer);
    glNamedFramebufferTextureLayer(fb, GL_COLOR_ATTACHMENT0, target.transmittance.get(), 0,
                                   plan.firstLayer + layer);
    // Only the texels that may not hold the cleared value, and only those the casters can reach
    // are drawn: llvmpipe clears RGBA32F a texel at a time.
    TexelRect& dirty = target.transmittanceDirty[plan.firstLayer + layer];
    scissorTo(dirty.united(drawn[layer]));
    glClearNamedFramebufferfv(fb, GL_COLOR, 0, clear);
    scissorTo(drawn[layer]);
    dirty = drawn[layer];
    program_.set("uView", layer);
    for (std::size_t index = 0; index < scene.draws().size(); ++index) {
      const GpuDraw& draw = scene.draws()[index];
      const GpuMaterial& material = scene.materials()[draw.material];
      const Material& m = material.desc;
      if ((casterLayers[index] >> layer & 1u) == 0) continue;
      program_.set("uObject", static_cast<int>(index));
      program_.set("uBaseColorFactor", m.baseColorFactor);
      program_.set("uHasBaseColorTexture", material.baseColor != 0 ? 1 : 0);
      program_.set("uBaseColorTexCoord", m.baseColorTexture.texCoord);
      program_.set("uBaseColorUvTransform", m.baseColorTexture.uvTransform);
      program_.set("uAlphaMode", static_cast<int>(m.alphaMode));
      program_.set("uAlphaCutoff", m.alphaCutoff);
      program_.set("uTransmission", m.transmissionFactor);
      program_.set("uHasTransmissionTexture", material.transmission != 0 ? 1 : 0);
      program_.set("uTransmissionTexCoord", m.transmissionTexture.texCoord);
      program_.set("uTransmissionUvTransform", m.transmissionTexture.uvTransform);
      glBindTextureUnit(contract::kTransmissionUnit, material.transmission);
      glBindSampler(contract::kTransmissionUnit, material.transmissionSampler);
      glBindTextureUnit(contract::kBaseColorUnit, material.baseColor);
      glBindSampler(contract::kBaseColorUnit, material.baseColorSampler);
      const GpuMeshRange& range = scene.meshes()[draw.mesh];
      glDrawElementsBaseVertex(
          GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4),
          range.baseVertex);
    }
  }
  gl::RasterState::restoreDefaults();
  glNamedFramebufferTexture(fb, GL_DEPTH_ATTACHMENT, 0, 0);
  glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, 0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the transmittance pass of light \"" + light.name + "\"");
}

}  // namespace omnishadow
