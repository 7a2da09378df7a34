#include "renderer/passes/transmittance_pass.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "renderer/core/errors.h"
#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/passes/texel_scissor.h"
#include "renderer/scene/translucency.h"
#include "renderer/view/caster_culling.h"

namespace omnishadow {

namespace {

constexpr unsigned kVolumeFeature = 1u, kDiffuseTransmissionFeature = 2u;

// What the casters a light's layers draw need of the program.
unsigned casterFeatures(const GpuScene& scene, const TranslucentReach& reach) {
  unsigned features = 0;
  for (std::size_t index = 0; index < scene.draws().size(); ++index) {
    if (reach.casterLayers[index] == 0u) continue;
    const Material& m = scene.materials()[scene.draws()[index].material].desc;
    if (volumeAttenuationExponent(m, 1.0f) != glm::vec3(0.0f)) features |= kVolumeFeature;
    if (hasDiffuseTransmission(m)) features |= kDiffuseTransmissionFeature;
  }
  return features;
}

}  // namespace

TransmittancePass::TransmittancePass() : framebuffer_(gl::createFramebuffer()) {}

const ShaderProgram& TransmittancePass::program(unsigned features) {
  std::unique_ptr<ShaderProgram>& slot = programs_[features];
  if (!slot) {
    std::vector<std::string> defines = {"TRANSMITTANCE"};
    if (features & kVolumeFeature) defines.emplace_back("VOLUME");
    if (features & kDiffuseTransmissionFeature) defines.emplace_back("DIFFUSE_TRANSMISSION");
    slot = std::make_unique<ShaderProgram>("shadow_depth.vert", "shadow_transmittance.frag",
                                           contract::withShaderContract(defines));
  }
  return *slot;
}

TranslucentReach translucentReach(const GpuScene& scene, const LightShadowPlan& plan,
                                  int resolution) {
  std::vector<ViewFrustum> views;
  for (int layer = 0; layer < plan.layerCount; ++layer)
    views.emplace_back(plan.viewProjection[layer]);
  TranslucentReach reach;
  reach.resolution = resolution;
  reach.texels.resize(static_cast<std::size_t>(plan.layerCount));
  reach.casterLayers.assign(scene.draws().size(), 0u);
  for (std::size_t index = 0; index < scene.draws().size(); ++index) {
    const GpuDraw& draw = scene.draws()[index];
    if (!isTranslucentCaster(scene.materials()[draw.material].desc)) continue;
    // The mesh's box as well as its sphere: Sundial's shadow decal, flat and oblique to the
    // light, reached 621x617 texels of a cube face by its sphere and 523x557 by both. llvmpipe
    // clears and copies each layer's rectangle a 16-byte texel at a time.
    const CasterBox box{draw.world, draw.meshBounds.min, draw.meshBounds.max};
    const unsigned layers = uniteCasterTexels(
        plan, casterViewMask(views, draw.boundsCenter, draw.boundsRadius), draw.boundsCenter,
        draw.boundsRadius, resolution, reach.texels, draw.meshBounds.empty() ? nullptr : &box);
    reach.casterLayers[index] = layers;
    reach.layers |= layers;
  }
  return reach;
}

std::vector<AtlasLayers> TransmittancePass::place(const std::vector<TranslucentReach>& reach,
                                                  std::vector<bool>& moved) {
  std::vector<AtlasLayers> places(reach.size());
  int layers = 0, width = 0, height = 0;
  for (std::size_t i = 0; i < reach.size(); ++i) {
    if (reach[i].layers == 0u) continue;
    places[i] = {layers, reach[i].layers};
    layers += std::popcount(reach[i].layers);
    for (const TexelRect& rect : reach[i].texels) {
      width = std::max(width, rect.x1 - rect.x0);
      height = std::max(height, rect.y1 - rect.y0);
    }
  }
  const bool grow = layers > layers_ || width > width_ || height > height_;
  if (grow) {
    GLint maxLayers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    if (layers > maxLayers)
      throw InputError("translucent shadows need " + std::to_string(layers) +
                       " transmittance layers, more than this GL's " + std::to_string(maxLayers) +
                       " (GL_MAX_ARRAY_TEXTURE_LAYERS): fewer lights with translucentShadows");
    width_ = std::max(width, width_);
    height_ = std::max(height, height_);
    layers_ = std::max(layers, layers_);
    atlas_ = gl::createTexture(GL_TEXTURE_2D_ARRAY);
    // 32-bit floats: A holds a depth the lighting pass compares with its own.
    glTextureStorage3D(atlas_.get(), 1, GL_RGBA32F, width_, height_, layers_);
    rectsBuffer_ = gl::createBuffer();
    const std::vector<glm::ivec4> empty(static_cast<std::size_t>(layers_), glm::ivec4(0));
    glNamedBufferStorage(rectsBuffer_.get(),
                         static_cast<GLsizeiptr>(empty.size() * sizeof(glm::ivec4)), empty.data(),
                         GL_DYNAMIC_STORAGE_BIT);
    rectsTexture_ = gl::createTexture(GL_TEXTURE_BUFFER);
    glTextureBuffer(rectsTexture_.get(), GL_RGBA32I, rectsBuffer_.get());
    gl::checkErrors("allocating the transmittance atlas");
  }
  moved.assign(reach.size(), false);
  for (std::size_t i = 0; i < reach.size(); ++i)
    moved[i] =
        places[i].layers != 0u && (grow || i >= placed_.size() || !(placed_[i] == places[i]));
  placed_ = places;
  return places;
}

void TransmittancePass::attachTarget(const TexelRect& rect, int atlasLayer, int resolution) {
  const GLuint fb = framebuffer_.get();
  if (rect.x0 == 0 && rect.y0 == 0) {
    glNamedFramebufferTextureLayer(fb, GL_COLOR_ATTACHMENT0, atlas_.get(), 0, atlasLayer);
    return;
  }
  if (resolution > scratchResolution_) {
    scratchResolution_ = resolution;
    scratch_ = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(scratch_.get(), 1, GL_RGBA32F, resolution, resolution);
  }
  glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, scratch_.get(), 0);
}

void TransmittancePass::render(const GpuScene& scene, const Light& light,
                               const LightShadowPlan& plan, const ShadowGroupTextures& depth,
                               const TranslucentReach& reach, const AtlasLayers& atlasLayers) {
  if (reach.layers == 0u) return;
  const GLuint fb = framebuffer_.get();
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  glNamedFramebufferDrawBuffer(fb, GL_COLOR_ATTACHMENT0);
  glNamedFramebufferReadBuffer(fb, GL_NONE);
  gl::RasterState state;
  state.viewport = {0, 0, depth.key.resolution, depth.key.resolution};
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
  const unsigned features = casterFeatures(scene, reach);
  const ShaderProgram& shader = program(features);
  shader.use();
  shader.set("uViewProjections", plan.viewProjection.data(), plan.layerCount);
  shader.set("uDrawBase", 0);

  const float clear[4] = {1.0f, 1.0f, 1.0f, 0.0f};
  int atlasLayer = atlasLayers.first;
  for (int layer = 0; layer < plan.layerCount; ++layer) {
    if ((reach.layers >> layer & 1u) == 0) continue;
    const TexelRect& rect = reach.texels[static_cast<std::size_t>(layer)];
    glNamedFramebufferTextureLayer(fb, GL_DEPTH_ATTACHMENT, depth.depth.get(), 0,
                                   plan.firstLayer + layer);
    attachTarget(rect, atlasLayer, depth.key.resolution);
    // Only the rectangle is read back: it is all that is cleared and drawn.
    scissorTo(rect);
    glClearNamedFramebufferfv(fb, GL_COLOR, 0, clear);
    shader.set("uView", layer);
    for (std::size_t index = 0; index < scene.draws().size(); ++index) {
      const GpuDraw& draw = scene.draws()[index];
      const GpuMaterial& material = scene.materials()[draw.material];
      const Material& m = material.desc;
      if ((reach.casterLayers[index] >> layer & 1u) == 0) continue;
      shader.set("uObject", static_cast<int>(index));
      shader.set("uBaseColorFactor", m.baseColorFactor);
      shader.set("uHasBaseColorTexture", material.baseColor != 0 ? 1 : 0);
      shader.set("uBaseColorTexCoord", m.baseColorTexture.texCoord);
      shader.set("uBaseColorUvTransform", m.baseColorTexture.uvTransform);
      shader.set("uAlphaMode", static_cast<int>(m.alphaMode));
      shader.set("uAlphaCutoff", m.alphaCutoff);
      shader.set("uTransmission", m.transmissionFactor);
      shader.set("uHasTransmissionTexture", material.transmission != 0 ? 1 : 0);
      shader.set("uTransmissionTexCoord", m.transmissionTexture.texCoord);
      shader.set("uTransmissionUvTransform", m.transmissionTexture.uvTransform);
      glBindTextureUnit(contract::kTransmissionUnit, material.transmission);
      glBindSampler(contract::kTransmissionUnit, material.transmissionSampler);
      glBindTextureUnit(contract::kBaseColorUnit, material.baseColor);
      glBindSampler(contract::kBaseColorUnit, material.baseColorSampler);
      // Volumes and diffuse transmission (translucency.h); the textures are 0 unless the
      // lighting pass draws them, which is when these apply.
      if (features & kVolumeFeature) {
        shader.set("uVolumeAttenuationExponent",
                   volumeAttenuationExponent(m, volumeScale(draw.world)));
        shader.set("uHasThicknessTexture", material.thickness != 0 ? 1 : 0);
        shader.set("uThicknessTexCoord", m.thicknessTexture.texCoord);
        shader.set("uThicknessUvTransform", m.thicknessTexture.uvTransform);
        glBindTextureUnit(contract::kShadowThicknessUnit, material.thickness);
        glBindSampler(contract::kShadowThicknessUnit, material.thicknessSampler);
      }
      if (features & kDiffuseTransmissionFeature) {
        shader.set("uDiffuseTransmission",
                   hasDiffuseTransmission(m) ? m.diffuseTransmissionFactor : 0.0f);
        shader.set("uDiffuseTransmissionColor", m.diffuseTransmissionColorFactor);
        shader.set("uHasDiffuseTransmissionTexture", material.diffuseTransmission != 0 ? 1 : 0);
        shader.set("uDiffuseTransmissionTexCoord", m.diffuseTransmissionTexture.texCoord);
        shader.set("uDiffuseTransmissionUvTransform", m.diffuseTransmissionTexture.uvTransform);
        shader.set("uHasDiffuseTransmissionColorTexture",
                   material.diffuseTransmissionColor != 0 ? 1 : 0);
        shader.set("uDiffuseTransmissionColorTexCoord", m.diffuseTransmissionColorTexture.texCoord);
        shader.set("uDiffuseTransmissionColorUvTransform",
                   m.diffuseTransmissionColorTexture.uvTransform);
        for (const auto& [unit, texture, sampler] :
             {std::tuple{contract::kShadowDiffuseTransmissionUnit, material.diffuseTransmission,
                         material.diffuseTransmissionSampler},
              std::tuple{contract::kShadowDiffuseTransmissionColorUnit,
                         material.diffuseTransmissionColor,
                         material.diffuseTransmissionColorSampler}}) {
          glBindTextureUnit(unit, texture);
          glBindSampler(unit, sampler);
        }
      }
      const GpuMeshRange& range = scene.meshes()[draw.mesh];
      glDrawElementsBaseVertex(
          GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4),
          range.baseVertex);
    }
    if (rect.x0 != 0 || rect.y0 != 0)
      glCopyImageSubData(scratch_.get(), GL_TEXTURE_2D, 0, rect.x0, rect.y0, 0, atlas_.get(),
                         GL_TEXTURE_2D_ARRAY, 0, 0, 0, atlasLayer, rect.x1 - rect.x0,
                         rect.y1 - rect.y0, 1);
    const glm::ivec4 held(rect.x0, rect.y0, rect.x1, rect.y1);
    glNamedBufferSubData(rectsBuffer_.get(),
                         static_cast<GLintptr>(atlasLayer) * static_cast<GLintptr>(sizeof held),
                         sizeof held, &held);
    ++atlasLayer;
  }
  gl::RasterState::restoreDefaults();
  glNamedFramebufferTexture(fb, GL_DEPTH_ATTACHMENT, 0, 0);
  glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, 0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the transmittance pass of light \"" + light.name + "\"");
}

}  // namespace omnishadow
