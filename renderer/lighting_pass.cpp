#include "renderer/lighting_pass.h"

#include <cmath>

#include "renderer/errors.h"
#include "renderer/gl_debug.h"

namespace omnishadow {
namespace {

// std430 mirror of `Light` in shaders/lights.glsl.
struct GpuLight {
  glm::vec4 positionRange;
  glm::vec4 directionType;
  glm::vec4 radianceShadow;
  glm::vec4 spotFilter;
  glm::vec4 shadowParameters;
};

std::vector<std::string> variantDefines(Shading shading, PassOutputs outputs) {
  std::vector<std::string> defines;
  if (shading == Shading::Phong) defines.push_back("SHADING_PHONG");
  if (outputs == PassOutputs::Aovs) defines.push_back("WRITE_AOVS");
  if (outputs == PassOutputs::Layers) defines.push_back("WRITE_LAYERS");
  return defines;
}

int attachmentsFor(PassOutputs outputs) {
  switch (outputs) {
    case PassOutputs::Beauty:
      return 1;
    case PassOutputs::Aovs:
      return 3 + kVisibilityPerPass / 4;
    case PassOutputs::Layers:
      return 3;
  }
  return 1;
}

gl::Sampler makeRawDepthSampler() {
  gl::Sampler sampler = gl::createSampler();
  glSamplerParameteri(sampler.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
  return sampler;
}

gl::Sampler makeCompareSampler(GLenum filter) {
  gl::Sampler sampler = gl::createSampler();
  glSamplerParameteri(sampler.get(), GL_TEXTURE_MIN_FILTER, filter);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_MAG_FILTER, filter);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  // Reversed depth: the receiver is lit when its reference is at least the stored depth.
  glSamplerParameteri(sampler.get(), GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL);
  return sampler;
}

gl::Texture makeTarget(GLenum format, int width, int height) {
  gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.get(), 1, format, width, height);
  return texture;
}

void bindMaterial(const ShaderProgram& program, const GpuMaterial& m) {
  const Material& d = m.desc;
  program.set("uBaseColorFactor", d.baseColorFactor);
  program.set("uMetallicFactor", d.metallicFactor);
  program.set("uRoughnessFactor", d.roughnessFactor);
  program.set("uEmissive", d.emissiveFactor * d.emissiveStrength);
  program.set("uNormalScale", d.normalScale);
  program.set("uOcclusionStrength", d.occlusionStrength);
  program.set("uAlphaMode", static_cast<int>(d.alphaMode));
  program.set("uAlphaCutoff", d.alphaCutoff);
  const struct {
    const char* uniform;
    GLuint texture, sampler;
    int texCoord;
  } slots[] = {
      {"uBaseColorTexCoord", m.baseColor, m.baseColorSampler, d.baseColorTexture.texCoord},
      {"uMetallicRoughnessTexCoord", m.metallicRoughness, m.metallicRoughnessSampler,
       d.metallicRoughnessTexture.texCoord},
      {"uNormalTexCoord", m.normal, m.normalSampler, d.normalTexture.texCoord},
      {"uOcclusionTexCoord", m.occlusion, m.occlusionSampler, d.occlusionTexture.texCoord},
      {"uEmissiveTexCoord", m.emissive, m.emissiveSampler, d.emissiveTexture.texCoord},
  };
  for (GLuint unit = 0; unit < 5; ++unit) {
    program.set(slots[unit].uniform, slots[unit].texture ? slots[unit].texCoord : -1);
    glBindTextureUnit(unit, slots[unit].texture);
    glBindSampler(unit, slots[unit].sampler);
  }
}

}  // namespace

FrameTargets::FrameTargets(int width, int height, PassOutputs outputs)
    : width_(width), height_(height), framebuffer_(gl::createFramebuffer()) {
  const int count = attachmentsFor(outputs);
  std::vector<GLenum> drawBuffers;
  for (int i = 0; i < count; ++i) {
    colors_.push_back(makeTarget(GL_RGBA32F, width, height));
    glNamedFramebufferTexture(framebuffer_.get(), GL_COLOR_ATTACHMENT0 + i, colors_.back().get(),
                              0);
    drawBuffers.push_back(GL_COLOR_ATTACHMENT0 + i);
  }
  depth_ = makeTarget(GL_DEPTH_COMPONENT32F, width, height);
  glNamedFramebufferTexture(framebuffer_.get(), GL_DEPTH_ATTACHMENT, depth_.get(), 0);
  glNamedFramebufferDrawBuffers(framebuffer_.get(), count, drawBuffers.data());
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer_.get(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("cannot create a " + std::to_string(width) + "x" + std::to_string(height) +
                      " framebuffer (status 0x" + std::to_string(status) + ")");
}

LightingPass::LightingPass(Shading shading, PassOutputs outputs)
    : outputs_(outputs),
      program_("scene.vert", "lighting.frag", variantDefines(shading, outputs)),
      hardCompare_(makeCompareSampler(GL_NEAREST)),
      linearCompare_(makeCompareSampler(GL_LINEAR)),
      rawDepth_(makeRawDepthSampler()) {}

void LightingPass::uploadLights(const std::vector<ShadedLight>& lights, int debugLight) {
  if (debugLight >= 0 && debugLight < static_cast<int>(lights.size()) &&
      lights[debugLight].shadow) {
    glBindTextureUnit(24, lights[debugLight].shadow->cube.get());
    glBindSampler(24, rawDepth_.get());
  }
  std::vector<GpuLight> data;
  int shadowIndex = 0;
  for (const ShadedLight& shaded : lights) {
    const Light& l = *shaded.light;
    GpuLight g{};
    g.positionRange = glm::vec4(l.position, l.range);
    g.directionType = glm::vec4(glm::normalize(l.direction), static_cast<float>(l.type));
    float index = -1.0f;
    if (shaded.shadow) {
      const GLuint unit = 8 + static_cast<GLuint>(shadowIndex);
      glBindTextureUnit(unit, shaded.shadow->cube.get());
      glBindSampler(
          unit, l.shadow.filter == ShadowFilter::Hard ? hardCompare_.get() : linearCompare_.get());
      index = static_cast<float>(shadowIndex++);
      g.shadowParameters =
          glm::vec4(shaded.shadow->near, shaded.shadow->far, l.shadow.bias, l.shadow.slopeBias);
    }
    g.radianceShadow = glm::vec4(l.color * l.intensity, index);
    // KHR_lights_punctual's cone falloff as a scale and offset of cos(angle).
    const float cosOuter = std::cos(l.outerConeAngle);
    const float cosInner = std::cos(l.innerConeAngle);
    const float scale = 1.0f / std::max(0.001f, cosInner - cosOuter);
    g.spotFilter = glm::vec4(scale, -cosOuter * scale, static_cast<float>(l.shadow.filter),
                             shaded.shadow ? static_cast<float>(shaded.shadow->resolution) : 0.0f);
    data.push_back(g);
  }
  const GLsizeiptr size = std::max<GLsizeiptr>(sizeof(GpuLight), data.size() * sizeof(GpuLight));
  if (size > lightBufferSize_) {
    lightBuffer_ = gl::createBuffer();
    glNamedBufferStorage(lightBuffer_.get(), size, nullptr, GL_DYNAMIC_STORAGE_BIT);
    lightBufferSize_ = size;
  }
  if (!data.empty())
    glNamedBufferSubData(lightBuffer_.get(), 0, data.size() * sizeof(GpuLight), data.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, lightBuffer_.get());
  program_.set("uLightCount", static_cast<int>(data.size()));
}

void LightingPass::drawScene(const GpuScene& scene, bool blended) {
  for (std::size_t index = 0; index < scene.draws().size(); ++index) {
    const GpuDraw& draw = scene.draws()[index];
    const GpuMaterial& material = scene.materials()[draw.material];
    if ((material.desc.alphaMode == AlphaMode::Blend) != blended) continue;
    if (material.desc.doubleSided) {
      glDisable(GL_CULL_FACE);
    } else {
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
    }
    glFrontFace(draw.mirrored ? GL_CW : GL_CCW);
    program_.set("uModel", draw.world);
    program_.set("uNormalMatrix", draw.normalMatrix);
    bindMaterial(program_, material);
    const GpuMeshRange& range = scene.meshes()[draw.mesh];
    program_.set("uHasTangents", range.hasTangents ? 1 : 0);
    if (outputs_ == PassOutputs::Layers) {
      program_.set("uObjectId", static_cast<float>(index));
      program_.set("uMaterialId", static_cast<float>(draw.material));
    }
    glDrawElementsBaseVertex(
        GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4),
        range.baseVertex);
  }
}

void LightingPass::render(const GpuScene& scene, const ViewCamera& camera,
                          const std::vector<ShadedLight>& lights, const glm::vec3& ambient,
                          FrameTargets& targets, const PassParameters& parameters) {
  glBindFramebuffer(GL_FRAMEBUFFER, targets.framebuffer());
  glViewport(0, 0, targets.width(), targets.height());
  // Background: no coverage, lit (visibility 1), no object or material (id -1).
  const float zero[4] = {0, 0, 0, 0};
  const float lit[4] = {1, 1, 1, 1};
  const float noIds[4] = {0, -1, -1, 0};
  for (int i = 0; i < targets.attachmentCount(); ++i) {
    const float* value = outputs_ == PassOutputs::Aovs && i >= 3 ? lit
                         : outputs_ == PassOutputs::Layers && i == 2 && parameters.layerMode == 0
                             ? noIds
                             : zero;
    glClearNamedFramebufferfv(targets.framebuffer(), GL_COLOR, i, value);
  }
  const float clearDepth = 0.0f;
  glClearNamedFramebufferfv(targets.framebuffer(), GL_DEPTH, 0, &clearDepth);

  program_.use();
  program_.set("uViewProjection", camera.projection * camera.view);
  program_.set("uCameraPosition", camera.eye);
  program_.set("uAmbient", ambient);
  if (outputs_ == PassOutputs::Aovs) program_.set("uVisibilityBase", parameters.visibilityBase);
  if (outputs_ == PassOutputs::Layers) {
    program_.set("uLayerMode", parameters.layerMode);
    program_.set("uLayerLight", parameters.layerLight);
  }
  program_.set("uDebugView", static_cast<int>(parameters.debugView));
  program_.set("uDebugLight", parameters.debugLight);
  uploadLights(lights, parameters.debugLight);
  glBindVertexArray(scene.vertexArray());

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  drawScene(scene, false);

  // Blended surfaces over the opaque frame, unsorted; the AOVs keep the opaque surfaces.
  if (outputs_ == PassOutputs::Layers) {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::checkErrors("a layer pass");
    return;
  }
  glDepthMask(GL_FALSE);
  glEnablei(GL_BLEND, 0);
  glBlendFuncSeparatei(0, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  for (int i = 1; i < targets.attachmentCount(); ++i)
    glColorMaski(static_cast<GLuint>(i), GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  drawScene(scene, true);
  for (int i = 1; i < targets.attachmentCount(); ++i)
    glColorMaski(static_cast<GLuint>(i), GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisablei(GL_BLEND, 0);
  glDepthMask(GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the lighting pass");
}

}  // namespace omnishadow
