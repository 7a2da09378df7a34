#include "renderer/passes/lighting_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "renderer/core/errors.h"
#include "renderer/gl/gl_debug.h"
#include "renderer/gl/raster_state.h"
#include "renderer/gl/software_rasterizer.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/passes/texel_scissor.h"
#include "renderer/scene/srgb_transfer.h"
#include "renderer/view/draw_order.h"
#include "renderer/view/sheen_albedo_table.h"

namespace omnishadow {
namespace {

using contract::GpuLight;

// The scene's blended draws, farthest from the camera first (renderer/view/draw_order.h).
std::vector<std::size_t> blendedDrawOrder(const GpuScene& scene, const glm::mat4& view) {
  std::vector<DrawCenter> blended;
  for (std::size_t i = 0; i < scene.draws().size(); ++i) {
    const GpuDraw& draw = scene.draws()[i];
    if (scene.materials()[draw.material].desc.alphaMode == AlphaMode::Blend)
      blended.push_back({i, draw.boundsCenter});
  }
  return farthestFirst(blended, view);
}

// Every draw of the scene, nearest to the camera first (renderer/view/draw_order.h).
std::vector<std::size_t> nearestDrawOrder(const GpuScene& scene, const glm::mat4& view) {
  std::vector<DrawCenter> draws;
  draws.reserve(scene.draws().size());
  for (std::size_t i = 0; i < scene.draws().size(); ++i)
    draws.push_back({i, scene.draws()[i].boundsCenter, scene.draws()[i].boundsRadius});
  return nearestFirst(draws, view);
}

// Texture slots in unit order (kBaseColorUnit + i), as bits of a material variant.
constexpr const char* kMaterialTextureDefines[contract::kMaterialUnits] = {
    "BASE_COLOR_TEXTURE", "METALLIC_ROUGHNESS_TEXTURE", "NORMAL_TEXTURE", "OCCLUSION_TEXTURE",
    "EMISSIVE_TEXTURE"};
constexpr unsigned kSpecularGlossinessBit = 1u << contract::kMaterialUnits;
// KHR_materials_sheen: the sheen layer, and its texture.
constexpr unsigned kSheenBit = kSpecularGlossinessBit << 1;
constexpr unsigned kSheenTextureBit = kSheenBit << 1;
// KHR_materials_specular's factors.
constexpr unsigned kDielectricSpecularBit = kSheenTextureBit << 1;
// KHR_materials_clearcoat: the layer, and each of its textures.
constexpr unsigned kClearcoatBit = kDielectricSpecularBit << 1;
constexpr unsigned kClearcoatTextureBit = kClearcoatBit << 1;
constexpr unsigned kClearcoatRoughnessTextureBit = kClearcoatTextureBit << 1;
constexpr unsigned kClearcoatNormalTextureBit = kClearcoatRoughnessTextureBit << 1;
// KHR_materials_specular's textures, and a sheen roughness texture on a unit of its own.
constexpr unsigned kSpecularTextureBit = kClearcoatNormalTextureBit << 1;
constexpr unsigned kSpecularColorTextureBit = kSpecularTextureBit << 1;
constexpr unsigned kSheenRoughnessTextureBit = kSpecularColorTextureBit << 1;
// KHR_materials_transmission drawn see-through (it reads the scene behind on a unit of its
// own), and its texture.
constexpr unsigned kTransmissionBit = kSheenRoughnessTextureBit << 1;
constexpr unsigned kTransmissionTextureBit = kTransmissionBit << 1;
// KHR_materials_volume on a see-through material, and its thickness texture.
constexpr unsigned kVolumeBit = kTransmissionTextureBit << 1;
constexpr unsigned kThicknessTextureBit = kVolumeBit << 1;
// KHR_materials_dispersion on a volume.
constexpr unsigned kDispersionBit = kThicknessTextureBit << 1;
// KHR_materials_anisotropy, and its texture.
constexpr unsigned kAnisotropyBit = kDispersionBit << 1;
constexpr unsigned kAnisotropyTextureBit = kAnisotropyBit << 1;
// KHR_materials_iridescence, and each of its textures.
constexpr unsigned kIridescenceBit = kAnisotropyTextureBit << 1;
constexpr unsigned kIridescenceTextureBit = kIridescenceBit << 1;
constexpr unsigned kIridescenceThicknessTextureBit = kIridescenceTextureBit << 1;
// KHR_materials_diffuse_transmission, and each of its textures.
constexpr unsigned kDiffuseTransmissionBit = kIridescenceThicknessTextureBit << 1;
constexpr unsigned kDiffuseTransmissionTextureBit = kDiffuseTransmissionBit << 1;
constexpr unsigned kDiffuseTransmissionColorTextureBit = kDiffuseTransmissionTextureBit << 1;
// An iridescent material whose metallic is 0 everywhere (factor 0), or 1 everywhere (factor 1,
// no texture): the film is worked out over that base alone (it costs a 1280x720 frame it fills
// about 7 ms on llvmpipe), the other weighing 0.
constexpr unsigned kIridescenceDielectricOnlyBit = kDiffuseTransmissionColorTextureBit << 1;
constexpr unsigned kIridescenceMetalOnlyBit = kIridescenceDielectricOnlyBit << 1;
static_assert(kIridescenceMetalOnlyBit != 0u, "a material variant is 32 bits");
// The variant bit that makes a variant read each extension texture, in
// contract::ExtensionTexture order (the scene behind: every see-through variant).
constexpr unsigned kExtensionTextureBit[contract::kExtensionTextures] = {
    kSheenTextureBit,
    kSheenRoughnessTextureBit,
    kClearcoatTextureBit,
    kClearcoatRoughnessTextureBit,
    kClearcoatNormalTextureBit,
    kSpecularTextureBit,
    kSpecularColorTextureBit,
    kTransmissionTextureBit,
    kTransmissionBit,
    kThicknessTextureBit,
    kAnisotropyTextureBit,
    kIridescenceTextureBit,
    kIridescenceThicknessTextureBit,
    kDiffuseTransmissionTextureBit,
    kDiffuseTransmissionColorTextureBit};
// A see-through surface, its volume and its dispersion: drawn as the base material together
// when the scene behind has no unit.
constexpr unsigned kSeeThroughBits =
    kTransmissionBit | kTransmissionTextureBit | kVolumeBit | kThicknessTextureBit | kDispersionBit;
// What a variant whose extension textures do not fit leaves out.
constexpr unsigned kExtensionTextureBits =
    kSheenTextureBit | kSheenRoughnessTextureBit | kClearcoatTextureBit |
    kClearcoatRoughnessTextureBit | kClearcoatNormalTextureBit | kSpecularTextureBit |
    kSpecularColorTextureBit | kSeeThroughBits | kAnisotropyTextureBit | kIridescenceTextureBit |
    kIridescenceThicknessTextureBit | kDiffuseTransmissionTextureBit |
    kDiffuseTransmissionColorTextureBit;
// What Blinn-Phong leaves out: it has no layers (--shading phong draws the base material
// alone), but reads KHR_materials_specular's color for its own specular.
constexpr unsigned kPbrOnlyBits =
    kSheenBit | kSheenTextureBit | kSheenRoughnessTextureBit | kClearcoatBit |
    kClearcoatTextureBit | kClearcoatRoughnessTextureBit | kClearcoatNormalTextureBit |
    kSeeThroughBits | kAnisotropyBit | kAnisotropyTextureBit | kIridescenceBit |
    kIridescenceTextureBit | kIridescenceThicknessTextureBit | kIridescenceDielectricOnlyBit |
    kIridescenceMetalOnlyBit | kDiffuseTransmissionBit | kDiffuseTransmissionTextureBit |
    kDiffuseTransmissionColorTextureBit;

using ExtensionUnits = std::array<int, contract::kExtensionTextures>;

// The units of the extension textures `variant` reads, one each from `firstFree` on, in
// contract::ExtensionTexture order; -1 for those it does not read.
ExtensionUnits extensionTextureUnits(unsigned variant, int firstFree) {
  ExtensionUnits units;
  int next = firstFree;
  for (int i = 0; i < contract::kExtensionTextures; ++i)
    units[static_cast<std::size_t>(i)] = (variant & kExtensionTextureBit[i]) ? next++ : -1;
  return units;
}

int unitOf(const ExtensionUnits& units, contract::ExtensionTexture texture) {
  return units[static_cast<std::size_t>(texture)];
}

// The defines that put an environment light's textures on the units from `first` on
// (shaders/environment.glsl): the specular levels, the irradiance, the BRDF table.
std::vector<std::string> environmentUnitDefines(int first) {
  return {"ENVIRONMENT_SPECULAR_UNIT " + std::to_string(first),
          "ENVIRONMENT_IRRADIANCE_UNIT " + std::to_string(first + 1),
          "ENVIRONMENT_BRDF_UNIT " + std::to_string(first + 2)};
}

// What shaders/environment.glsl reads of an environment light besides its textures.
void setEnvironmentUniforms(const ShaderProgram& program, const EnvironmentBinding& environment) {
  program.set("uEnvironmentRotation", environment.toEnvironment);
  program.set("uEnvironmentScale", environment.scale);
  program.set("uEnvironmentMaxLevel", environment.textures->maxLevel());
}

std::vector<std::string> variantDefines(Shading shading, PassOutputs outputs,
                                        const LightingFeatures& features, unsigned material) {
  std::vector<std::string> defines;
  for (int i = 0; i < contract::kMaterialUnits; ++i)
    if (material & (1u << i)) defines.push_back(kMaterialTextureDefines[i]);
  if (material & kSpecularGlossinessBit) defines.push_back("SPECULAR_GLOSSINESS");
  if (material & kDielectricSpecularBit) {
    defines.push_back("DIELECTRIC_SPECULAR");
    if (material & kSpecularTextureBit) defines.push_back("SPECULAR_TEXTURE");
    if (material & kSpecularColorTextureBit) defines.push_back("SPECULAR_COLOR_TEXTURE");
  }
  // LightingPass::materialVariant() leaves the layers out of Phong variants.
  if (material & kSheenBit) {
    defines.push_back("SHEEN");
    if (material & kSheenTextureBit) defines.push_back("SHEEN_TEXTURE");
    if (material & kSheenRoughnessTextureBit) defines.push_back("SHEEN_ROUGHNESS_TEXTURE");
  }
  if (material & kClearcoatBit) {
    defines.push_back("CLEARCOAT");
    if (material & kClearcoatTextureBit) defines.push_back("CLEARCOAT_TEXTURE");
    if (material & kClearcoatRoughnessTextureBit) defines.push_back("CLEARCOAT_ROUGHNESS_TEXTURE");
    if (material & kClearcoatNormalTextureBit) defines.push_back("CLEARCOAT_NORMAL_TEXTURE");
  }
  if (material & kTransmissionBit) {
    defines.push_back("TRANSMISSION");
    if (material & kTransmissionTextureBit) defines.push_back("TRANSMISSION_TEXTURE");
    if (material & kVolumeBit) defines.push_back("VOLUME");
    if (material & kThicknessTextureBit) defines.push_back("THICKNESS_TEXTURE");
    if (material & kDispersionBit) defines.push_back("DISPERSION");
  }
  if (material & kAnisotropyBit) {
    defines.push_back("ANISOTROPY");
    if (material & kAnisotropyTextureBit) defines.push_back("ANISOTROPY_TEXTURE");
  }
  if (material & kDiffuseTransmissionBit) {
    defines.push_back("DIFFUSE_TRANSMISSION");
    if (material & kDiffuseTransmissionTextureBit)
      defines.push_back("DIFFUSE_TRANSMISSION_TEXTURE");
    if (material & kDiffuseTransmissionColorTextureBit)
      defines.push_back("DIFFUSE_TRANSMISSION_COLOR_TEXTURE");
  }
  if (material & kIridescenceBit) {
    defines.push_back("IRIDESCENCE");
    if (material & kIridescenceTextureBit) defines.push_back("IRIDESCENCE_TEXTURE");
    if (material & kIridescenceThicknessTextureBit)
      defines.push_back("IRIDESCENCE_THICKNESS_TEXTURE");
    if (material & kIridescenceDielectricOnlyBit) defines.push_back("IRIDESCENCE_DIELECTRIC_ONLY");
    if (material & kIridescenceMetalOnlyBit) defines.push_back("IRIDESCENCE_METAL_ONLY");
  }
  if (features.cubeShadows) defines.push_back("SHADOW_CUBE");
  if (features.planarShadows) defines.push_back("SHADOW_PLANAR");
  // Both layouts' arrays get the same size: llvmpipe evaluates both sides of a light-type
  // branch, so a cube array is also indexed with planar slots (an index past a one-slot array
  // crashed LLVM's compile). At least one slot.
  defines.push_back("SHADOW_SLOTS " + std::to_string(std::max(1, features.shadowSlots)));
  const ShadowSamplerUnits units = shadowSamplerUnits(features);
  const struct {
    int unit;
    const char* define;
  } arrays[] = {
      {units.cubeCompare, "CUBE_COMPARE_UNIT"}, {units.planarCompare, "PLANAR_COMPARE_UNIT"},
      {units.cubeDepth, "CUBE_DEPTH_UNIT"},     {units.planarDepth, "PLANAR_DEPTH_UNIT"},
      {units.cubeMoments, "CUBE_MOMENTS_UNIT"}, {units.planarMoments, "PLANAR_MOMENTS_UNIT"}};
  for (const auto& a : arrays)
    if (a.unit >= 0) defines.push_back(std::string(a.define) + " " + std::to_string(a.unit));
  if (units.environment >= 0) {
    defines.push_back("ENVIRONMENT");
    for (std::string& define : environmentUnitDefines(units.environment))
      defines.push_back(std::move(define));
  }
  if (units.ambientOcclusion >= 0 && readsAmbientOcclusion(outputs)) {
    defines.push_back("AMBIENT_OCCLUSION");
    defines.push_back("AMBIENT_OCCLUSION_UNIT " + std::to_string(units.ambientOcclusion));
  }
  const ExtensionUnits extensionUnits = extensionTextureUnits(material, units.end);
  for (int i = 0; i < contract::kExtensionTextures; ++i)
    if (const int unit = extensionUnits[static_cast<std::size_t>(i)]; unit >= 0)
      defines.push_back(std::string(contract::kExtensionTextureUnitDefines[i]) + " " +
                        std::to_string(unit));
  const struct {
    ShadowFilter filter;
    const char* define;
  } filters[] = {
      {ShadowFilter::Hard, "SHADOW_HARD"},        {ShadowFilter::Pcf, "SHADOW_PCF"},
      {ShadowFilter::PcfDisk, "SHADOW_PCF_DISK"}, {ShadowFilter::Poisson, "SHADOW_POISSON"},
      {ShadowFilter::Pcss, "SHADOW_PCSS"},        {ShadowFilter::Vsm, "SHADOW_VSM"}};
  for (const auto& f : filters)
    if (features.filters & (1u << static_cast<unsigned>(f.filter))) defines.push_back(f.define);
  if (features.debugViews) defines.push_back("DEBUG_VIEWS");
  if (features.debugDepth) defines.push_back("DEBUG_DEPTH");
  if (features.translucentShadows) defines.push_back("TRANSLUCENT_SHADOWS");
  if (features.clusteredLights) defines.push_back("CLUSTERED_LIGHTS");
  if (features.spotLights) defines.push_back("SPOT_LIGHTS");
  if (features.directionalLights) defines.push_back("DIRECTIONAL_LIGHTS");
  if (features.lightsInStorage) defines.push_back("LIGHTS_IN_STORAGE");
  if (shading == Shading::Phong) defines.push_back("SHADING_PHONG");
  if (outputs == PassOutputs::Aovs) {
    defines.push_back("WRITE_AOVS");
    defines.push_back("VISIBILITY_OUTPUTS " + std::to_string(features.visibilityOutputs));
  }
  if (outputs == PassOutputs::Layers) defines.push_back("WRITE_LAYERS");
  if (writesSrgb8(outputs)) defines.push_back("WRITE_SRGB8");
  if (writesIdsBesideBeauty(outputs)) defines.push_back("WITH_IDS");
  if (outputs == PassOutputs::Ids) defines.push_back("WRITE_IDS");
  // The AOV and layer passes report every light's terms, also where it faces away.
  if (features.facingLightLoop && !features.debugViews &&
      (outputs == PassOutputs::Beauty || outputs == PassOutputs::BeautyIds || writesSrgb8(outputs)))
    defines.push_back("FACING_LIGHT_LOOP");
  return contract::withShaderContract(std::move(defines));
}

std::string hex(GLenum value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%04X", static_cast<unsigned>(value));
  return text;
}

int attachmentsFor(PassOutputs outputs, int visibilityOutputs) {
  switch (outputs) {
    case PassOutputs::Beauty:
    case PassOutputs::Srgb8:
    case PassOutputs::Ids:
      return 1;
    case PassOutputs::Srgb8Ids:
    case PassOutputs::BeautyIds:
      return 2;
    case PassOutputs::Aovs:
      return 3 + visibilityOutputs;
    case PassOutputs::Layers:
      return 3;
  }
  return 1;
}

// Spot and directional maps: outside the map is lit. With reversed depth that is a border
// depth of 0, the cleared "nothing here" value (the shader also skips points outside).
void clampToLitBorder(GLuint sampler) {
  const float border[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (const GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glSamplerParameteri(sampler, wrap, GL_CLAMP_TO_BORDER);
  glSamplerParameterfv(sampler, GL_TEXTURE_BORDER_COLOR, border);
}

// Clamped to the edge; with `filter` for raw reads (depth as a number, VSM moments).
gl::Sampler makeRawSampler(GLenum filter) {
  gl::Sampler sampler = gl::createSampler();
  glSamplerParameteri(sampler.get(), GL_TEXTURE_MIN_FILTER, filter);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_MAG_FILTER, filter);
  for (const GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glSamplerParameteri(sampler.get(), wrap, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(sampler.get(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
  return sampler;
}

// Hardware depth comparison with bilinear weights (the 2x2 PCF of every tap).
gl::Sampler makeCompareSampler(bool planar) {
  gl::Sampler sampler = makeRawSampler(GL_LINEAR);
  if (planar) clampToLitBorder(sampler.get());
  glSamplerParameteri(sampler.get(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  // Reversed depth: the receiver is lit when its reference is at least the stored depth.
  glSamplerParameteri(sampler.get(), GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL);
  return sampler;
}

GLenum colorFormat(PassOutputs outputs, int attachment) {
  switch (outputs) {
    case PassOutputs::Srgb8:
      return GL_RGBA8UI;
    case PassOutputs::Srgb8Ids:  // no blended surface: no coverage to keep beside the id
      return attachment == 0 ? GL_RGBA8UI : GL_R32F;
    case PassOutputs::BeautyIds:
      return attachment == 0 ? GL_RGBA32F : GL_RG32F;
    case PassOutputs::Ids:
      return GL_RG32F;
    default:
      return GL_RGBA32F;
  }
}

// Bytes of a texel of attachment `attachment`.
double texelBytes(PassOutputs outputs, int attachment) {
  switch (colorFormat(outputs, attachment)) {
    case GL_RGBA8UI:
      return 4.0;
    case GL_RG32F:
      return 2.0 * sizeof(float);
    case GL_R32F:
      return sizeof(float);
    default:
      return 4.0 * sizeof(float);
  }
}

gl::Texture makeTarget(GLenum format, int width, int height) {
  gl::Texture texture = gl::createTexture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.get(), 1, format, width, height);
  return texture;
}

// A normal texture's +X (growing u) and +Y (up: shrinking v) as directions in the mesh's tangent
// frame, which follows the mesh's own UVs: with t = L uv + offset, the texture's axes are L's
// inverse applied to them, with v's sign flipped on both sides for "up", normalized so that a
// scale changes no normal. Identity (exactly) for the identity transform.
glm::mat3 normalTextureAxes(const glm::mat3& uvTransform) {
  const glm::mat2 flipV(1.0f, 0.0f, 0.0f, -1.0f);
  const glm::mat2 axes = flipV * glm::inverse(glm::mat2(uvTransform)) * flipV;
  const float x = glm::length(axes[0]), y = glm::length(axes[1]);
  if (!(x > 0.0f) || !(y > 0.0f)) return glm::mat3(1.0f);
  return glm::mat3(glm::vec3(axes[0] / x, 0.0f), glm::vec3(axes[1] / y, 0.0f),
                   glm::vec3(0.0f, 0.0f, 1.0f));
}

// A material extension's texture as the lighting shader reads it: its texCoord (-1: not read)
// and transform uniforms, and the unit it is bound to.
struct ExtensionTextureBinding {
  const char* texCoord;
  const char* transform;
  int unit;
  GLuint texture, sampler;
  const TextureSlot& slot;
  unsigned bit;  // the variant bit that declares it
};

// Binds what `variant` declares of `textures`; the others' units may hold the frame's shadow
// arrays, and are left alone.
void bindExtensionTextures(const ShaderProgram& program, unsigned variant,
                           std::initializer_list<ExtensionTextureBinding> textures) {
  for (const ExtensionTextureBinding& t : textures) {
    if (!(variant & t.bit)) continue;
    program.set(t.texCoord, t.texture ? t.slot.texCoord : -1);
    program.set(t.transform, t.slot.uvTransform);
    glBindTextureUnit(static_cast<GLuint>(t.unit), t.texture);
    glBindSampler(static_cast<GLuint>(t.unit), t.sampler);
  }
}

// What shaders/depth_masked.frag reads of a masked material: its base color's alpha and cutoff.
void bindAlphaCutoff(const ShaderProgram& program, const GpuMaterial& m) {
  const Material& d = m.desc;
  program.set("uBaseColorFactor", d.baseColorFactor);
  program.set("uBaseColorTexCoord", m.baseColor ? d.baseColorTexture.texCoord : -1);
  program.set("uBaseColorUvTransform", d.baseColorTexture.uvTransform);
  program.set("uAlphaCutoff", d.alphaCutoff);
  glBindTextureUnit(contract::kBaseColorUnit, m.baseColor);
  glBindSampler(contract::kBaseColorUnit, m.baseColorSampler);
}

// KHR_materials_volume's Beer's law as exp(-coefficient x distance): -ln(attenuationColor) /
// attenuationDistance per channel, 0 at an infinite distance. A color of 0 counts as 1e-30, so
// that the uniform stays finite: a tenth of the distance then lets through a thousandth.
glm::vec3 attenuationCoefficient(const Material& d) {
  if (!std::isfinite(d.attenuationDistance)) return glm::vec3(0.0f);
  glm::vec3 coefficient;
  for (int c = 0; c < 3; ++c)
    coefficient[c] = -std::log(std::max(d.attenuationColor[c], 1e-30f)) / d.attenuationDistance;
  return coefficient;
}

// Sets the material's uniforms and binds its textures for a program of `variant`, whose
// extension textures take `units` (extensionTextureUnits), the scene behind see-through
// surfaces among them.
void bindMaterial(const ShaderProgram& program, const GpuMaterial& m, unsigned variant,
                  const ExtensionUnits& units, GLuint sceneBehind) {
  using contract::ExtensionTexture;
  const Material& d = m.desc;
  program.set("uBaseColorFactor", d.baseColorFactor);
  program.set("uMetallicFactor", d.metallicFactor);
  program.set("uRoughnessFactor", d.roughnessFactor);
  program.set("uEmissive", d.emissiveFactor * d.emissiveStrength);
  program.set("uNormalScale", d.normalScale);
  program.set("uOcclusionStrength", d.occlusionStrength);
  program.set("uAlphaMode", static_cast<int>(d.alphaMode));
  program.set("uAlphaCutoff", d.alphaCutoff);
  program.set("uNormalTextureAxes", normalTextureAxes(d.normalTexture.uvTransform));
  program.set("uUnlit", d.unlit ? 1 : 0);
  program.set("uSpecularGlossiness", d.specularGlossiness ? 1 : 0);
  program.set("uSpecularFactor", d.specularFactor);
  program.set("uGlossinessFactor", d.glossinessFactor);
  program.set("uDielectricF0", dielectricF0(d));
  program.set("uSpecularWeight", d.specularWeight);
  program.set("uSpecularColorFactor", d.specularColorFactor);
  const TextureSlot& specularOrMetallic =
      d.specularGlossiness ? d.specularGlossinessTexture : d.metallicRoughnessTexture;
  const struct {
    const char* uniform;
    const char* transform;
    GLuint texture, sampler;
    const TextureSlot& slot;
  } slots[] = {
      {"uBaseColorTexCoord", "uBaseColorUvTransform", m.baseColor, m.baseColorSampler,
       d.baseColorTexture},
      {"uMetallicRoughnessTexCoord", "uMetallicRoughnessUvTransform", m.metallicRoughness,
       m.metallicRoughnessSampler, specularOrMetallic},
      {"uNormalTexCoord", "uNormalUvTransform", m.normal, m.normalSampler, d.normalTexture},
      {"uOcclusionTexCoord", "uOcclusionUvTransform", m.occlusion, m.occlusionSampler,
       d.occlusionTexture},
      {"uEmissiveTexCoord", "uEmissiveUvTransform", m.emissive, m.emissiveSampler,
       d.emissiveTexture},
  };
  // In unit order: slot i is unit kBaseColorUnit + i.
  static_assert(contract::kMetallicRoughnessUnit == contract::kBaseColorUnit + 1 &&
                contract::kNormalUnit == contract::kBaseColorUnit + 2 &&
                contract::kOcclusionUnit == contract::kBaseColorUnit + 3 &&
                contract::kEmissiveUnit == contract::kBaseColorUnit + 4 &&
                contract::kMaterialUnits == 5);
  for (int i = 0; i < contract::kMaterialUnits; ++i) {
    const auto unit = static_cast<GLuint>(contract::kBaseColorUnit + i);
    program.set(slots[i].uniform, slots[i].texture ? slots[i].slot.texCoord : -1);
    program.set(slots[i].transform, slots[i].slot.uvTransform);
    glBindTextureUnit(unit, slots[i].texture);
    glBindSampler(unit, slots[i].sampler);
  }
  bindExtensionTextures(
      program, variant,
      {{"uSpecularTexCoord", "uSpecularUvTransform", unitOf(units, ExtensionTexture::Specular),
        m.specular, m.specularSampler, d.specularTexture, kSpecularTextureBit},
       {"uSpecularColorTexCoord", "uSpecularColorUvTransform",
        unitOf(units, ExtensionTexture::SpecularColor), m.specularColor, m.specularColorSampler,
        d.specularColorTexture, kSpecularColorTextureBit}});
  if (hasClearcoat(d)) {
    program.set("uClearcoatFactor", d.clearcoatFactor);
    program.set("uClearcoatRoughnessFactor", d.clearcoatRoughnessFactor);
    program.set("uClearcoatNormalScale", d.clearcoatNormalScale);
    program.set("uClearcoatNormalTextureAxes",
                normalTextureAxes(d.clearcoatNormalTexture.uvTransform));
    bindExtensionTextures(
        program, variant,
        {{"uClearcoatTexCoord", "uClearcoatUvTransform", unitOf(units, ExtensionTexture::Clearcoat),
          m.clearcoat, m.clearcoatSampler, d.clearcoatTexture, kClearcoatTextureBit},
         {"uClearcoatRoughnessTexCoord", "uClearcoatRoughnessUvTransform",
          unitOf(units, ExtensionTexture::ClearcoatRoughness), m.clearcoatRoughness,
          m.clearcoatRoughnessSampler, d.clearcoatRoughnessTexture, kClearcoatRoughnessTextureBit},
         {"uClearcoatNormalTexCoord", "uClearcoatNormalUvTransform",
          unitOf(units, ExtensionTexture::ClearcoatNormal), m.clearcoatNormal,
          m.clearcoatNormalSampler, d.clearcoatNormalTexture, kClearcoatNormalTextureBit}});
  }
  if (variant & kTransmissionBit) {
    program.set("uTransmissionFactor", d.transmissionFactor);
    program.set("uIor", d.ior);
    const auto unit = static_cast<GLuint>(unitOf(units, ExtensionTexture::SceneBehind));
    glBindTextureUnit(unit, sceneBehind);
    glBindSampler(unit, 0);
    bindExtensionTextures(
        program, variant,
        {{"uTransmissionTexCoord", "uTransmissionUvTransform",
          unitOf(units, ExtensionTexture::Transmission), m.transmission, m.transmissionSampler,
          d.transmissionTexture, kTransmissionTextureBit}});
  }
  if (variant & kVolumeBit) {
    program.set("uThicknessFactor", d.thicknessFactor);
    program.set("uAttenuationCoefficient", attenuationCoefficient(d));
    program.set("uDispersion", d.dispersion);
    bindExtensionTextures(
        program, variant,
        {{"uThicknessTexCoord", "uThicknessUvTransform", unitOf(units, ExtensionTexture::Thickness),
          m.thickness, m.thicknessSampler, d.thicknessTexture, kThicknessTextureBit}});
  }
  if (variant & kAnisotropyBit) {
    program.set("uAnisotropyStrength", d.anisotropyStrength);
    program.set("uAnisotropyRotation",
                glm::vec2(std::cos(d.anisotropyRotation), std::sin(d.anisotropyRotation)));
    bindExtensionTextures(program, variant,
                          {{"uAnisotropyTexCoord", "uAnisotropyUvTransform",
                            unitOf(units, ExtensionTexture::Anisotropy), m.anisotropy,
                            m.anisotropySampler, d.anisotropyTexture, kAnisotropyTextureBit}});
  }
  if (variant & kDiffuseTransmissionBit) {
    program.set("uDiffuseTransmissionFactor", d.diffuseTransmissionFactor);
    program.set("uDiffuseTransmissionColorFactor", d.diffuseTransmissionColorFactor);
    bindExtensionTextures(
        program, variant,
        {{"uDiffuseTransmissionTexCoord", "uDiffuseTransmissionUvTransform",
          unitOf(units, ExtensionTexture::DiffuseTransmission), m.diffuseTransmission,
          m.diffuseTransmissionSampler, d.diffuseTransmissionTexture,
          kDiffuseTransmissionTextureBit},
         {"uDiffuseTransmissionColorTexCoord", "uDiffuseTransmissionColorUvTransform",
          unitOf(units, ExtensionTexture::DiffuseTransmissionColor), m.diffuseTransmissionColor,
          m.diffuseTransmissionColorSampler, d.diffuseTransmissionColorTexture,
          kDiffuseTransmissionColorTextureBit}});
  }
  if (variant & kIridescenceBit) {
    program.set("uIridescenceFactor", d.iridescenceFactor);
    program.set("uIridescenceIor", d.iridescenceIor);
    program.set("uIridescenceThicknessMinimum", d.iridescenceThicknessMinimum);
    program.set("uIridescenceThicknessMaximum", d.iridescenceThicknessMaximum);
    bindExtensionTextures(program, variant,
                          {{"uIridescenceTexCoord", "uIridescenceUvTransform",
                            unitOf(units, ExtensionTexture::Iridescence), m.iridescence,
                            m.iridescenceSampler, d.iridescenceTexture, kIridescenceTextureBit},
                           {"uIridescenceThicknessTexCoord", "uIridescenceThicknessUvTransform",
                            unitOf(units, ExtensionTexture::IridescenceThickness),
                            m.iridescenceThickness, m.iridescenceThicknessSampler,
                            d.iridescenceThicknessTexture, kIridescenceThicknessTextureBit}});
  }
  if (!hasSheen(d)) return;
  program.set("uSheenColorFactor", d.sheenColorFactor);
  program.set("uSheenRoughnessFactor", d.sheenRoughnessFactor);
  // The sheen texture holds the color and, when it is the same image (or the color has none),
  // the roughness; a roughness texture of another image has a unit of its own, read only where
  // the variant declares it (texCoord -1: not read).
  // A variant whose extension textures do not fit reads none (materialVariant()).
  const bool sheenRead = (variant & kSheenTextureBit) != 0;
  const bool colorRead = sheenRead && d.sheenColorTexture.texture >= 0;
  const bool roughnessRead =
      d.sheenRoughnessTexture.texture >= 0 &&
      (m.sheenRoughness ? (variant & kSheenRoughnessTextureBit) != 0 : sheenRead);
  program.set("uSheenColorTexCoord", colorRead ? d.sheenColorTexture.texCoord : -1);
  program.set("uSheenColorUvTransform", d.sheenColorTexture.uvTransform);
  program.set("uSheenRoughnessTexCoord", roughnessRead ? d.sheenRoughnessTexture.texCoord : -1);
  program.set("uSheenRoughnessUvTransform", d.sheenRoughnessTexture.uvTransform);
  if (sheenRead) {
    const auto unit = static_cast<GLuint>(unitOf(units, ExtensionTexture::Sheen));
    glBindTextureUnit(unit, m.sheen);
    glBindSampler(unit, m.sheenSampler);
  }
  if (variant & kSheenRoughnessTextureBit) {
    const auto unit = static_cast<GLuint>(unitOf(units, ExtensionTexture::SheenRoughness));
    glBindTextureUnit(unit, m.sheenRoughness);
    glBindSampler(unit, m.sheenRoughnessSampler);
  }
}

}  // namespace

AovVisibilityLayout aovVisibilityLayout(int lights, bool rgbTerms) {
  AovVisibilityLayout layout;
  const auto targetsFor = [](int channels) { return (channels + 3) / 4; };
  if (rgbTerms && lights <= kMaxCombinedLights) {
    layout.combined = true;
    layout.scalarPerPass = 4;  // one target
    layout.rgbPerPass = lights;
    layout.outputs = 1 + targetsFor(3 * lights);
    return layout;
  }
  constexpr int kMost = contract::kMaxVisibilityOutputs;
  layout.outputs = std::clamp(targetsFor(lights), 1, kMost);
  if (rgbTerms)
    layout.outputs = std::max(layout.outputs, targetsFor(3 * std::min(lights, 4 * kMost / 3)));
  layout.scalarPerPass = 4 * layout.outputs;
  layout.rgbPerPass = rgbTerms ? 4 * layout.outputs / 3 : 0;
  return layout;
}

FrameTargets::FrameTargets(int width, int height, PassOutputs outputs, int visibilityOutputs,
                           bool madeZeroed, bool zerosByUpload)
    : width_(width),
      height_(height),
      outputs_(outputs),
      visibilityOutputs_(outputs == PassOutputs::Aovs ? visibilityOutputs : 0),
      madeZeroed_(madeZeroed),
      zerosByUpload_(zerosByUpload),
      framebuffer_(gl::createFramebuffer()) {
  const int count = attachmentsFor(outputs, visibilityOutputs);
  std::vector<GLenum> drawBuffers;
  for (int i = 0; i < count; ++i) {
    colors_.push_back(makeTarget(colorFormat(outputs, i), width, height));
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
                      " framebuffer (status " + hex(status) + ")");
}

TexelRegion FrameTargets::toClear(int clearValues, bool zeros) const {
  if (!clearValues_ && madeZeroed_ && zeros) return {};
  if (clearValues_ != clearValues) return TexelRegion(TexelRect::whole(width_, height_));
  return drawn_;
}

void FrameTargets::cleared(int clearValues, const TexelRegion& drawn) {
  clearValues_ = clearValues;
  drawn_ = drawn;
}

void FrameTargets::uploadZeros(int attachment, const TexelRegion& region) {
  if (colorFormat(outputs_, attachment) != GL_RGBA32F)
    throw std::logic_error("zeros uploaded into a frame target that is not RGBA32F");
  const TexelRegion within = region.clipped(TexelRect::whole(width_, height_));
  const auto floats = static_cast<std::size_t>(within.largestRectTexels()) * 4;
  if (zeros_.size() < floats) zeros_.resize(floats, 0.0f);
  for (const TexelRect& r : within.rects())
    glTextureSubImage2D(colors_[static_cast<std::size_t>(attachment)].get(), 0, r.x0, r.y0,
                        r.x1 - r.x0, r.y1 - r.y0, GL_RGBA, GL_FLOAT, zeros_.data());
}

double FrameTargets::bytes(int width, int height, PassOutputs outputs) {
  const double texels = static_cast<double>(width) * height;
  double texel = sizeof(float);  // the depth
  for (int i = 0; i < attachmentsFor(outputs, contract::kMaxVisibilityOutputs); ++i)
    texel += texelBytes(outputs, i);
  return texels * texel;
}

LightingFeatures lightingFeatures(const std::vector<Light>& lights, DebugView debugView) {
  LightingFeatures features;
  std::size_t viewProjections = 0;  // at most: a directional light has up to kMaxCascades
  for (const Light& light : lights) {
    if (light.type != LightType::Directional && light.range > 0.0f) features.clusteredLights = true;
    if (light.type == LightType::Spot) features.spotLights = true;
    if (light.type == LightType::Directional) features.directionalLights = true;
    if (!light.shadow.enabled) continue;
    (light.type == LightType::Point ? features.cubeShadows : features.planarShadows) = true;
    features.filters |= 1u << static_cast<unsigned>(light.shadow.filter);
    if (light.type != LightType::Point) viewProjections += contract::kMaxCascades;
  }
  features.lightsInStorage = lights.size() > contract::kMaxUniformLights ||
                             viewProjections > contract::kMaxUniformViewProjections;
  // The cascade view reads the debug light's cascade where the depth view reads its map.
  features.debugViews = debugView != DebugView::None;
  features.debugDepth = debugView == DebugView::Depth || debugView == DebugView::Cascade;
  features.facingLightLoop = !features.clusteredLights && lights.size() <= kMaxFacingLoopLights;
  return features;
}

ShadowSamplerUnits shadowSamplerUnits(const LightingFeatures& features) {
  const auto reads = [&](std::initializer_list<ShadowFilter> filters) {
    for (ShadowFilter f : filters)
      if (features.filters & (1u << static_cast<unsigned>(f))) return true;
    return false;
  };
  // Which filter reads which family: shaders/shadows.glsl refuses to compile where a family it
  // reads has no unit.
  const bool compare =
      reads({ShadowFilter::Pcf, ShadowFilter::PcfDisk, ShadowFilter::Poisson, ShadowFilter::Pcss});
  const bool depth = reads({ShadowFilter::Hard, ShadowFilter::Pcss}) || features.debugDepth;
  const bool moments = reads({ShadowFilter::Vsm});
  const int slots = std::max(1, features.shadowSlots);
  const auto layout = [&](int first) {
    ShadowSamplerUnits units;
    int next = first;
    const auto take = [&](bool used, int& unit) {
      if (!used) return;
      unit = next;
      next += slots;
    };
    take(compare && features.cubeShadows, units.cubeCompare);
    take(compare && features.planarShadows, units.planarCompare);
    take(depth && features.cubeShadows, units.cubeDepth);
    take(depth && features.planarShadows, units.planarDepth);
    take(moments && features.cubeShadows, units.cubeMoments);
    take(moments && features.planarShadows, units.planarMoments);
    if (features.environment) {
      units.environment = next;
      next += 3;
    }
    if (features.ambientOcclusion) units.ambientOcclusion = next++;
    units.end = next;
    return units;
  };
  return layout(contract::kFirstShadowUnit);
}

void setShadowSlots(const ShadowAtlasPlan& atlas, LightingFeatures& features) {
  int cube = 0, planar = 0;
  for (const ShadowGroupPlan& group : atlas.groups)
    ++(group.key.layout == ShadowLayout::Cube ? cube : planar);
  features.shadowSlots = std::max(cube, planar);
}

LightingPass::LightingPass(Shading shading, PassOutputs outputs, const LightingFeatures& features)
    : shading_(shading),
      outputs_(outputs),
      features_(features),
      shadowUnits_(shadowSamplerUnits(features)),
      depthOnly_("scene.vert", "depth_only.frag", contract::shaderContractDefines()),
      cubeCompare_(makeCompareSampler(false)),
      planarCompare_(makeCompareSampler(true)),
      rawDepth_(makeRawSampler(GL_NEAREST)),
      moments_(makeRawSampler(GL_LINEAR)) {}

unsigned LightingPass::materialVariant(const GpuMaterial& material) const {
  const GLuint textures[contract::kMaterialUnits] = {material.baseColor, material.metallicRoughness,
                                                     material.normal, material.occlusion,
                                                     material.emissive};
  unsigned variant = material.desc.specularGlossiness ? kSpecularGlossinessBit : 0u;
  for (int i = 0; i < contract::kMaterialUnits; ++i)
    if (textures[i] != 0) variant |= 1u << i;
  if (hasDielectricSpecular(material.desc)) {
    variant |= kDielectricSpecularBit;
    if (material.specular != 0) variant |= kSpecularTextureBit;
    if (material.specularColor != 0) variant |= kSpecularColorTextureBit;
  }
  if (hasSheen(material.desc)) {
    variant |= kSheenBit | (material.sheen != 0 ? kSheenTextureBit : 0u);
    if (material.sheenRoughness != 0) variant |= kSheenRoughnessTextureBit;
  }
  if (hasTransmission(material.desc)) {
    variant |= kTransmissionBit;
    if (material.transmission != 0) variant |= kTransmissionTextureBit;
    if (hasVolume(material.desc))
      variant |= kVolumeBit | (material.thickness != 0 ? kThicknessTextureBit : 0u) |
                 (hasDispersion(material.desc) ? kDispersionBit : 0u);
  }
  if (hasAnisotropy(material.desc))
    variant |= kAnisotropyBit | (material.anisotropy != 0 ? kAnisotropyTextureBit : 0u);
  if (hasDiffuseTransmission(material.desc)) {
    variant |= kDiffuseTransmissionBit |
               (material.diffuseTransmission != 0 ? kDiffuseTransmissionTextureBit : 0u) |
               (material.diffuseTransmissionColor != 0 ? kDiffuseTransmissionColorTextureBit : 0u);
  }
  if (hasIridescence(material.desc)) {
    variant |= kIridescenceBit | (material.iridescence != 0 ? kIridescenceTextureBit : 0u) |
               (material.iridescenceThickness != 0 ? kIridescenceThicknessTextureBit : 0u);
    if (material.desc.metallicFactor == 0.0f)
      variant |= kIridescenceDielectricOnlyBit;
    else if (material.desc.metallicFactor == 1.0f && material.metallicRoughness == 0)
      variant |= kIridescenceMetalOnlyBit;
  }
  if (hasClearcoat(material.desc)) {
    variant |= kClearcoatBit;
    if (material.clearcoat != 0) variant |= kClearcoatTextureBit;
    if (material.clearcoatRoughness != 0) variant |= kClearcoatRoughnessTextureBit;
    if (material.clearcoatNormal != 0) variant |= kClearcoatNormalTextureBit;
  }
  if (shading_ == Shading::Phong) variant &= ~kPbrOnlyBits;
  // The extension textures take the units after the frame's shadow arrays; a variant whose
  // textures would reach past the last unit draws those extensions from their factors.
  const ExtensionUnits units = extensionTextureUnits(variant, shadowUnits_.end);
  if (*std::max_element(units.begin(), units.end()) >= contract::kTextureUnits)
    variant &= ~kExtensionTextureBits;
  return variant;
}

LightingPass::DrawSet LightingPass::drawSet(std::size_t material, const GpuScene& scene) const {
  return drawSetOf(frameVariants_[material], scene.materials()[material]);
}

LightingPass::DrawSet LightingPass::drawSetOf(unsigned variant, const GpuMaterial& material) {
  // See-through: hasTransmission, but not in Phong frames, which draw the base material alone,
  // nor where the scene behind would have no texture unit (materialVariant()).
  if (variant & kTransmissionBit) return DrawSet::SeeThrough;
  const AlphaMode mode = material.desc.alphaMode;
  return mode == AlphaMode::Opaque ? DrawSet::Opaque
         : mode == AlphaMode::Mask ? DrawSet::Masked
                                   : DrawSet::Blended;
}

bool LightingPass::drawnInSet(const GpuDraw& draw, DrawSet set) {
  // One of each set of repeated draws: the one that wins the depth test among them, so that
  // the ids are the same as with all of them. Opaque surfaces test GL_GEQUAL (the last of equal
  // depths wins; the nearest-first order keeps the scene's order for equal spheres), masked
  // ones GL_GREATER (the first wins). See-through and blended surfaces read or blend what lies
  // under them, and every copy counts.
  if (set == DrawSet::Opaque) return !draw.repeatedLater;
  if (set == DrawSet::Masked) return !draw.repeatsEarlier;
  return true;
}

LightingPass::SeeThrough LightingPass::seeThrough(const GpuScene& scene,
                                                  const glm::mat4& view) const {
  SeeThrough found;
  std::vector<DrawCenter> draws;
  for (std::size_t i = 0; i < scene.draws().size(); ++i) {
    const GpuDraw& draw = scene.draws()[i];
    if (drawSet(draw.material, scene) != DrawSet::SeeThrough) continue;
    const GpuMaterial& material = scene.materials()[draw.material];
    found.any = true;
    draws.push_back({i, draw.boundsCenter});
    // lighting.frag reads level log2(size) x roughness x clamp(2 ior - 2, 0, 1), and a
    // roughness texture only multiplies the factor.
    const Material& d = material.desc;
    if (d.roughnessFactor > 0.0f && d.ior > 1.0f) found.blurred = true;
  }
  found.order = farthestFirst(draws, view);
  return found;
}

namespace {

// The screen rectangle (x0, y0, x1, y1 in NDC) that a bounding sphere covers at most: its box's
// corners projected; the whole screen when some corner lies behind the eye.
glm::vec4 screenBounds(const glm::mat4& viewProjection, const glm::vec3& center, float radius) {
  glm::vec4 bounds(1e30f, 1e30f, -1e30f, -1e30f);
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 offset((corner & 1) ? radius : -radius, (corner & 2) ? radius : -radius,
                           (corner & 4) ? radius : -radius);
    const glm::vec4 clip = viewProjection * glm::vec4(center + offset, 1.0f);
    if (!(clip.w > 1e-6f)) return {-1.0f, -1.0f, 1.0f, 1.0f};
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    bounds = {std::min(bounds.x, ndc.x), std::min(bounds.y, ndc.y), std::max(bounds.z, ndc.x),
              std::max(bounds.w, ndc.y)};
  }
  return bounds;
}

bool overlap(const glm::vec4& a, const glm::vec4& b) {
  return a.x <= b.z && b.x <= a.z && a.y <= b.w && b.y <= a.w;
}

// The pixels a lighting pass of `scene` may draw: its draws' boxes projected, each with a pixel
// more for the points and lines (a pixel wide, centred on their vertices).
TexelRegion drawnPixels(const GpuScene& scene, const glm::mat4& viewProjection,
                        const FrameTargets& targets) {
  const int width = targets.width(), height = targets.height();
  const TexelRect whole = TexelRect::whole(width, height);
  std::vector<TexelRect> draws;
  draws.reserve(scene.draws().size());
  for (const GpuDraw& draw : scene.draws()) {
    if (draw.meshBounds.empty()) continue;  // no vertex
    draws.push_back(ndcTexelRect(projectedBox(viewProjection, draw.world, draw.meshBounds.min,
                                              draw.meshBounds.max),
                                 width, height)
                        .grown(1, 1, width, height));
    // A room seen from inside: nothing more to learn.
    if (draws.back() == whole) return TexelRegion(whole);
  }
  return TexelRegion::unionOf(draws, whole);
}

}  // namespace

void LightingPass::drawSeeThrough(const GpuScene& scene, const SeeThrough& seen,
                                  const glm::mat4& viewProjection, const FrameTargets& targets,
                                  const FrameUniforms& uniforms) {
  // The screen bounds of the draws since the last copy, which it does not hold.
  std::vector<glm::vec4> sinceCopy;
  const auto copy = [&] {
    copySceneBehind(targets, seen.blurred);
    sinceCopy.clear();
  };
  for (std::size_t k = 0; k < seen.order.size(); ++k) {
    const GpuDraw& draw = scene.draws()[seen.order[k]];
    const glm::vec4 bounds = screenBounds(viewProjection, draw.boundsCenter, draw.boundsRadius);
    if (k == 0 || std::any_of(sinceCopy.begin(), sinceCopy.end(),
                              [&](const glm::vec4& other) { return overlap(other, bounds); }))
      copy();
    const std::vector<std::size_t> one = {seen.order[k]};
    // A closed thin wall shows its far side through its near side. A flat mesh shows one side.
    const bool twoWalls = scene.materials()[draw.material].desc.doubleSided &&
                          !(frameVariants_[draw.material] & kVolumeBit) && !draw.plane;
    if (twoWalls) {
      drawScene(scene, DrawSet::SeeThrough, nullptr, uniforms, &one, GL_BACK);
      copy();
      drawScene(scene, DrawSet::SeeThrough, nullptr, uniforms, &one, GL_FRONT);
    } else {
      drawScene(scene, DrawSet::SeeThrough, nullptr, uniforms, &one);
    }
    sinceCopy.push_back(bounds);
  }
}

void LightingPass::copySceneBehind(const FrameTargets& targets, bool mipmaps) {
  const int w = targets.width(), h = targets.height();
  if (!sceneBehind_ || behindWidth_ != w || behindHeight_ != h) {
    // Half floats: what shows through is tinted and, on rough surfaces, blurred; the levels
    // down to 1x1 let the roughest read an average of the whole frame.
    const int levels = 1 + static_cast<int>(std::floor(std::log2(std::max(w, h))));
    sceneBehind_ = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(sceneBehind_.get(), levels, GL_RGBA16F, w, h);
    glTextureParameteri(sceneBehind_.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(sceneBehind_.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(sceneBehind_.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(sceneBehind_.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    behindFramebuffer_ = gl::createFramebuffer();
    glNamedFramebufferTexture(behindFramebuffer_.get(), GL_COLOR_ATTACHMENT0, sceneBehind_.get(),
                              0);
    behindWidth_ = w;
    behindHeight_ = h;
  }
  glNamedFramebufferReadBuffer(targets.framebuffer(), GL_COLOR_ATTACHMENT0);
  glBlitNamedFramebuffer(targets.framebuffer(), behindFramebuffer_.get(), 0, 0, w, h, 0, 0, w, h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
  // Surfaces that read level 0 alone spare the frame the levels (and read no stale ones).
  glTextureParameteri(sceneBehind_.get(), GL_TEXTURE_MAX_LEVEL,
                      mipmaps ? 1000 : 0);  // GL's default: every level
  if (mipmaps) glGenerateTextureMipmap(sceneBehind_.get());
}

const ShaderProgram& LightingPass::program(unsigned variant) {
  for (const auto& [key, program] : programs_)
    if (key == variant) return *program;
  programs_.emplace_back(variant, std::make_unique<ShaderProgram>(
                                      "scene.vert", "lighting.frag",
                                      variantDefines(shading_, outputs_, features_, variant)));
  const ShaderProgram& made = *programs_.back().second;
  if (variant & kSheenBit) {
    // As vec4s: a float array may take a vec4's room per element (GL allows either), and
    // fragment uniforms are 4096 components on some drivers.
    static_assert(kSheenAlbedoEntries % 4 == 0);
    const std::array<float, kSheenAlbedoEntries>& table = sheenAlbedoTable();
    std::array<glm::vec4, kSheenAlbedoEntries / 4> packed;
    for (std::size_t i = 0; i < packed.size(); ++i)
      packed[i] = glm::vec4(table[4 * i], table[4 * i + 1], table[4 * i + 2], table[4 * i + 3]);
    made.set("uSheenAlbedo", packed.data(), static_cast<int>(packed.size()));
  }
  if (writesSrgb8(outputs_)) {
    const std::array<float, 256>& steps = srgb8Steps();
    made.set("uSrgb8Next", steps.data(), static_cast<int>(steps.size()));
  }
  return made;
}

void LightingPass::compileMaterialVariants(const GpuScene& scene) {
  for (const GpuDraw& draw : scene.draws())
    program(materialVariant(scene.materials()[draw.material]));
}

template <typename T>
void LightingPass::bindLightBlock(gl::StreamBuffer& buffer, std::vector<T>& items,
                                  int storageBinding, int uniformBinding,
                                  std::size_t uniformCapacity) const {
  if (features_.lightsInStorage) {
    // Blocks are bound with at least one element, even when nothing reads it.
    if (items.empty()) items.emplace_back();
    buffer.upload(items);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(storageBinding), buffer.get());
    return;
  }
  // lightingFeatures() bounds what the frame can upload; a uniform block is bound whole.
  if (items.size() > uniformCapacity)
    throw std::logic_error("a light uniform block overflows: lightsInStorage was not set");
  items.resize(uniformCapacity);
  buffer.upload(items);
  glBindBufferBase(GL_UNIFORM_BUFFER, static_cast<GLuint>(uniformBinding), buffer.get());
}

int LightingPass::uploadLights(const std::vector<ShadedLight>& lights,
                               const ShadowGroups& shadowGroups,
                               const TransmittanceAtlas& transmittanceAtlas) {
  // Each group takes the next slot of its layout's sampler arrays.
  std::vector<int> slot(shadowGroups.size());
  int cubeSlots = 0, planarSlots = 0;
  for (std::size_t g = 0; g < shadowGroups.size(); ++g) {
    const ShadowGroupTextures& group = shadowGroups[g];
    const bool cube = group.key.layout == ShadowLayout::Cube;
    const int s = slot[g] = cube ? cubeSlots++ : planarSlots++;
    // Only the arrays the frame's filters read are declared, and bound.
    const auto bind = [&](int firstUnit, GLuint texture, GLuint sampler) {
      if (firstUnit < 0 || !texture) return;
      glBindTextureUnit(static_cast<GLuint>(firstUnit + s), texture);
      glBindSampler(static_cast<GLuint>(firstUnit + s), sampler);
    };
    const ShadowSamplerUnits& u = shadowUnits_;
    bind(cube ? u.cubeCompare : u.planarCompare, group.depth.get(),
         cube ? cubeCompare_.get() : planarCompare_.get());
    bind(cube ? u.cubeDepth : u.planarDepth, group.depth.get(), rawDepth_.get());
    bind(cube ? u.cubeMoments : u.planarMoments, group.moments ? group.moments.get() : 0,
         moments_.get());
  }
  glBindTextureUnit(contract::kTransmittanceUnit, transmittanceAtlas.layers);
  glBindTextureUnit(contract::kTransmittanceRectsUnit, transmittanceAtlas.rects);

  std::vector<GpuLight> data;
  std::vector<glm::mat4> viewProjections;
  for (const ShadedLight& shaded : lights) {
    const Light& l = *shaded.light;
    const ShadowSettings& s = l.shadow;
    GpuLight g{};
    g.positionRange = glm::vec4(l.position, l.range);
    g.directionType = glm::vec4(glm::normalize(l.direction), static_cast<float>(l.type));
    float group = -1.0f;
    if (const LightShadowPlan* plan = shaded.shadow) {
      group = static_cast<float>(slot[plan->group]);
      g.shadowDepth = glm::vec4(plan->near, plan->far, s.bias, s.slopeBias);
      g.shadowBias = glm::vec4(s.minBias, s.normalBias, s.filterRadius, s.samples);
      g.shadowSoft = glm::vec4(s.radius, s.bleedReduction, plan->firstLayer, plan->layerCount);
      g.shadowProjection = glm::vec4(
          plan->tanHalfFov, static_cast<float>(viewProjections.size()),
          shaded.translucent ? 1.0f + static_cast<float>(shaded.transmittanceLayers) : 0.0f,
          static_cast<float>(shaded.transmittanceFirst));
      for (int c = 0; c < 4; ++c) {
        g.cascadeEnd[c] = plan->cascadeEnd[c];
        g.cascadeTexel[c] = plan->cascadeTexel[c];
      }
      if (l.type != LightType::Point)
        viewProjections.insert(viewProjections.end(), plan->viewProjection.begin(),
                               plan->viewProjection.begin() + plan->layerCount);
    }
    g.radianceShadow = glm::vec4(l.color * l.intensity, group);
    // KHR_lights_punctual's cone falloff as a scale and offset of cos(angle).
    const float cosOuter = std::cos(l.outerConeAngle);
    const float cosInner = std::cos(l.innerConeAngle);
    const float scale = 1.0f / std::max(0.001f, cosInner - cosOuter);
    g.spotFilter = glm::vec4(scale, -cosOuter * scale, static_cast<float>(s.filter),
                             static_cast<float>(s.resolution));
    data.push_back(g);
  }
  const int lightCount = static_cast<int>(data.size());
  bindLightBlock(lightBuffer_, data, contract::kLightsBinding, contract::kLightsUniformBinding,
                 contract::kMaxUniformLights);
  bindLightBlock(viewProjectionBuffer_, viewProjections, contract::kShadowViewProjectionsBinding,
                 contract::kShadowViewProjectionsUniformBinding,
                 contract::kMaxUniformViewProjections);
  return lightCount;
}

void LightingPass::uploadClusters(const GpuScene& scene, const std::vector<ShadedLight>& lights,
                                  const ViewCamera& camera, FrameUniforms& uniforms) {
  std::vector<const Light*> list;
  for (const ShadedLight& shaded : lights) list.push_back(shaded.light);
  const glm::vec4 depthRow = viewDepthRow(camera.view);
  float farthest = 0.0f;
  for (const GpuDraw& draw : scene.draws())
    farthest = std::max(farthest,
                        glm::dot(depthRow, glm::vec4(draw.boundsCenter, 1.0f)) + draw.boundsRadius);
  LightClusters clusters = buildLightClusters(list, camera, farthest, 16, 24, &clusterBoxes_);
  static_assert(std::is_same_v<decltype(clusters.ranges)::value_type, contract::GpuClusterIndex> &&
                std::is_same_v<decltype(clusters.lights)::value_type, contract::GpuClusterIndex>);
  if (clusters.lights.empty()) clusters.lights.push_back(0);  // bound with at least one element
  clusterRanges_.upload(clusters.ranges);
  clusterLights_.upload(clusters.lights);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kClusterRangesBinding, clusterRanges_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, contract::kClusterLightsBinding, clusterLights_.get());
  uniforms.viewDepth = depthRow;
  uniforms.clusters = std::move(clusters);
}

void LightingPass::setFrameUniforms(const ShaderProgram& program,
                                    const FrameUniforms& uniforms) const {
  const PassParameters& parameters = uniforms.parameters;
  program.set("uViewProjection", uniforms.viewProjection);
  program.set("uCameraPosition", uniforms.cameraPosition);
  program.set("uAmbient", uniforms.ambience.ambient);
  if (features_.environment) setEnvironmentUniforms(program, uniforms.ambience.environment);
  if (readsOcclusion())  // render() checked that the frame has it
    program.set("uAmbientOcclusionStrength", uniforms.ambience.occlusion->strength);
  if (outputs_ == PassOutputs::Aovs) {
    program.set("uVisibilityBase", parameters.visibilityBase);
    program.set("uScalarTerms", parameters.scalarTerms);
    program.set("uRgbFirst", parameters.rgbFirst);
  }
  if (writesSrgb8(outputs_)) program.set("uExposureScale", parameters.exposureScale);
  if (outputs_ == PassOutputs::Layers) {
    program.set("uLayerMode", parameters.layerMode);
    program.set("uLayerLight", parameters.layerLight);
  }
  program.set("uDebugView", static_cast<int>(parameters.debugView));
  program.set("uDebugLight", parameters.debugLight);
  program.set("uCameraView", uniforms.cameraView);
  program.set("uLightCount", uniforms.lightCount);
  if (!features_.clusteredLights) return;
  const LightClusters& clusters = uniforms.clusters;
  program.set("uTileSize", clusters.tileSize);
  program.set("uTileColumns", clusters.columns);
  program.set("uTileRows", clusters.rows);
  program.set("uSlices", clusters.slices);
  program.set("uSliceNear", clusters.sliceNear);
  program.set("uSliceScale", clusters.sliceScale);
  program.set("uViewDepth", uniforms.viewDepth);
  program.set("uGlobalLights", static_cast<int>(clusters.globalCount));
}

void LightingPass::drawScene(const GpuScene& scene, DrawSet set, const ShaderProgram* depthOnly,
                             const FrameUniforms& uniforms, const std::vector<std::size_t>* only,
                             GLenum faces) {
  const bool lighting = depthOnly == nullptr;
  const ShaderProgram* current = depthOnly;
  if (depthOnly) depthOnly->use();
  const std::vector<std::size_t>& order = only                      ? *only
                                          : set == DrawSet::Blended ? blendedOrder_
                                                                    : nearestOrder_;
  for (const std::size_t index : order) {
    const GpuDraw& draw = scene.draws()[index];
    const GpuMaterial& material = scene.materials()[draw.material];
    const DrawSet drawSet = this->drawSet(draw.material, scene);
    if (drawSet != set || !drawnInSet(draw, set)) continue;
    // GL does not blend into integer targets: the renderer gives frames with blended surfaces
    // the float target.
    if (drawSet == DrawSet::Blended && writesSrgb8(outputs_))
      throw std::logic_error("the 8-bit beauty pass cannot draw blended surfaces");
    const unsigned variant = lighting ? frameVariants_[draw.material] : 0u;
    if (lighting) {
      const ShaderProgram& wanted = program(variant);
      if (&wanted != current) {
        current = &wanted;
        wanted.use();
        if (std::find(framePrograms_.begin(), framePrograms_.end(), variant) ==
            framePrograms_.end()) {
          setFrameUniforms(wanted, uniforms);
          framePrograms_.push_back(variant);
        }
      }
    }
    const ShaderProgram& program = *current;
    // A mirrored transform turns the winding around, so front faces are the clockwise ones.
    const auto winding = static_cast<GLenum>(draw.mirrored ? GL_CW : GL_CCW);
    if (faces == GL_FRONT_AND_BACK)
      gl::CullState{!material.desc.doubleSided, GL_BACK, winding}.apply();
    else
      gl::CullState{true, static_cast<GLenum>(faces == GL_FRONT ? GL_BACK : GL_FRONT), winding}
          .apply();
    program.set("uModel", draw.world);
    if (!lighting && set == DrawSet::Masked) bindAlphaCutoff(program, material);
    const GpuMeshRange& range = scene.meshes()[draw.mesh];
    if (lighting) {
      program.set("uNormalMatrix", draw.normalMatrix);
      bindMaterial(program, material, variant, extensionTextureUnits(variant, shadowUnits_.end),
                   sceneBehind_.get());
      program.set("uHasTangents", range.hasTangents ? 1 : 0);
      if (outputs_ == PassOutputs::Layers || outputs_ == PassOutputs::Ids ||
          writesIdsBesideBeauty(outputs_)) {
        program.set("uObjectId", static_cast<float>(index));
        program.set("uMaterialId", static_cast<float>(draw.material));
      }
    }
    const auto drawTriangles = [&] {
      glDrawElementsBaseVertex(
          GL_TRIANGLES, range.indexCount, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(range.firstIndex) * 4),
          range.baseVertex);
    };
    if (set == DrawSet::Blended && material.desc.doubleSided) {
      // Its back faces, then its front faces, so that "over" puts the side facing the camera
      // over the far side of a closed glass (as three.js and Filament draw them).
      gl::CullState{true, GL_FRONT, winding}.apply();
      drawTriangles();
      gl::CullState{true, GL_BACK, winding}.apply();
    }
    drawTriangles();
    if (range.lineIndexCount + range.pointIndexCount > 0)
      drawPointsAndLines(range, program, lighting);
  }
}

// One pixel wide (GL's default line width and point size), in their base color: the lighting
// program skips the lights for them (uUnlit), and the shadow pass never draws them.
void LightingPass::drawPointsAndLines(const GpuMeshRange& range, const ShaderProgram& program,
                                      bool lighting) {
  if (lighting) program.set("uUnlit", 1);
  std::uintptr_t first = static_cast<std::uintptr_t>(range.firstIndex + range.indexCount);
  for (const auto& [primitive, count] : {std::pair{GLenum{GL_LINES}, range.lineIndexCount},
                                         std::pair{GLenum{GL_POINTS}, range.pointIndexCount}}) {
    if (count > 0) {
      glDrawElementsBaseVertex(primitive, count, GL_UNSIGNED_INT,
                               reinterpret_cast<const void*>(first * 4), range.baseVertex);
    }
    first += static_cast<std::uintptr_t>(count);
  }
  if (lighting) program.set("uUnlit", 0);
}

std::array<float, 4> LightingPass::clearValue(int attachment,
                                              const PassParameters& parameters) const {
  // Background: no coverage, lit (visibility 1), no object or material (id -1).
  const int i = attachment;
  if (outputs_ == PassOutputs::Aovs && i >= 3) return {1, 1, 1, 1};
  if (outputs_ == PassOutputs::Layers && i == 2 && parameters.layerMode == 0) return {0, -1, -1, 0};
  if (outputs_ == PassOutputs::Ids || (writesIdsBesideBeauty(outputs_) && i == 1))
    return {-1, 0, 0, 0};
  return {0, 0, 0, 0};  // the 8-bit beauty's too, in integers
}

void LightingPass::clearTargets(FrameTargets& targets, const PassParameters& parameters,
                                const TexelRegion* zerosOver) const {
  for (int i = 0; i < targets.attachmentCount(); ++i) {
    const std::array<float, 4> value = clearValue(i, parameters);
    if (writesSrgb8(outputs_) && i == 0) {
      const GLuint black[4] = {0, 0, 0, 0};
      glClearNamedFramebufferuiv(targets.framebuffer(), GL_COLOR, i, black);
    } else if (zerosOver && colorFormat(outputs_, i) == GL_RGBA32F &&
               value == std::array<float, 4>{0, 0, 0, 0}) {
      targets.uploadZeros(i, *zerosOver);
    } else {
      glClearNamedFramebufferfv(targets.framebuffer(), GL_COLOR, i, value.data());
    }
  }
  const float clearDepth = 0.0f;  // zero bytes, as clearValue()'s zeros
  glClearNamedFramebufferfv(targets.framebuffer(), GL_DEPTH, 0, &clearDepth);
}

void LightingPass::render(const GpuScene& scene, const ViewCamera& camera,
                          const std::vector<ShadedLight>& lights, const ShadowGroups& shadowGroups,
                          const TransmittanceAtlas& transmittanceAtlas,
                          const LightingAmbience& ambience, FrameTargets& targets,
                          const PassParameters& parameters) {
  if (features_.environment != (ambience.environment.textures != nullptr))
    throw std::logic_error("a lighting pass drawn with another environment than it was made for");
  if (features_.ambientOcclusion != ambience.occlusion.has_value())
    throw std::logic_error("a lighting pass drawn with another ambient occlusion than made for");
  glBindFramebuffer(GL_FRAMEBUFFER, targets.framebuffer());
  const glm::mat4 viewProjection = camera.projection * camera.view;
  const bool background = ambience.environment.background && outputs_ != PassOutputs::Aovs &&
                          outputs_ != PassOutputs::Layers && outputs_ != PassOutputs::Ids &&
                          parameters.debugView == DebugView::None;
  // Only the layers' mode changes what the targets are cleared to (clearTargets()).
  const int clearValues = outputs_ == PassOutputs::Layers && parameters.layerMode == 0 ? 1 : 0;
  const TexelRect whole = TexelRect::whole(targets.width(), targets.height());
  bool zeros = true;
  for (int i = 0; i < targets.attachmentCount(); ++i)
    zeros = zeros && clearValue(i, parameters) == std::array<float, 4>{0, 0, 0, 0};
  // One scissored clear of the stale pixels' bounds: a clear per rectangle of Sundial's drawn
  // region (15 to 43 of them) cost the lighting pass more than their fewer texels saved. Uploads
  // of zeros, a row copy each, can take the region's rectangles alone.
  const TexelRegion staleRegion = targets.toClear(clearValues, zeros);
  const TexelRect stale = staleRegion.bounds();
  if (staleRegion == TexelRegion(whole)) {
    clearTargets(targets, parameters);
  } else if (!stale.empty()) {  // empty: every pixel holds what the clear would write
    scissorTo(stale);
    clearTargets(targets, parameters, targets.zerosByUpload() ? &staleRegion : nullptr);
    gl::Scissor{}.apply();
  }
  targets.cleared(clearValues,
                  background ? TexelRegion(whole) : drawnPixels(scene, viewProjection, targets));

  FrameUniforms uniforms;
  uniforms.viewProjection = viewProjection;
  uniforms.cameraPosition = camera.eye;
  uniforms.ambience = ambience;
  if (const EnvironmentTextures* environment = ambience.environment.textures) {
    const auto unit = static_cast<GLuint>(shadowUnits_.environment);
    const GLuint textures[3] = {environment->specular(), environment->irradiance(),
                                environment->brdf()};
    const GLuint samplers[3] = {environment->sampler(), environment->sampler(),
                                environment->tableSampler()};
    for (GLuint i = 0; i < 3; ++i) {
      glBindTextureUnit(unit + i, textures[i]);
      glBindSampler(unit + i, samplers[i]);
    }
  }
  uniforms.parameters = parameters;
  uniforms.cameraView = parameters.cascadeView ? *parameters.cascadeView : camera.view;
  uniforms.lightCount = uploadLights(lights, shadowGroups, transmittanceAtlas);
  if (features_.clusteredLights) uploadClusters(scene, lights, camera, uniforms);
  framePrograms_.clear();
  blendedOrder_ = blendedDrawOrder(scene, camera.view);
  nearestOrder_ = nearestDrawOrder(scene, camera.view);
  frameVariants_.clear();
  for (const GpuMaterial& material : scene.materials())
    frameVariants_.push_back(materialVariant(material));
  glBindVertexArray(scene.vertexArray());

  // With the pre-pass (PassParameters::depthPrepass), depth of the opaque surfaces first, so
  // the expensive shading runs once per pixel instead of once per overlapping surface. Then
  // opaque surfaces shade where their depth is the pre-pass's (no depth writes: early depth
  // tests stay on), masked ones test and write as usual.
  gl::RasterState state;
  state.viewport = {0, 0, targets.width(), targets.height()};
  const bool occluded = readsOcclusion();
  if (parameters.blendedOnly) {
    // These passes report the blended surfaces' AOVs, not their light.
    if (occluded) {
      occlusionPass().clear(targets.width(), targets.height());
      occlusionEstimated_ = false;
      bindOcclusion();
    }
    state.apply();
    drawScene(scene, DrawSet::Blended, nullptr, uniforms);
    gl::RasterState::restoreDefaults();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::checkErrors("a pass over the blended surfaces");
    return;
  }
  if (parameters.depthPrepass) {
    state.color.rgba = {false, false, false, false};
    state.apply();
    drawDepth(scene, DrawSet::Opaque, depthOnly_, uniforms);
  }
  if (occluded && parameters.reuseOcclusion && occlusionEstimated_) {
    bindOcclusion();
  } else if (occluded) {
    estimateOcclusion(scene, camera, targets, parameters, uniforms);
    occlusionEstimated_ = true;
    glBindFramebuffer(GL_FRAMEBUFFER, targets.framebuffer());
    glBindVertexArray(scene.vertexArray());
  }
  // Equal depths pass both ways, so the last drawn of equally near surfaces wins either way.
  state.color.rgba = {true, true, true, true};
  state.depth.func = GL_GEQUAL;
  state.depth.write = !parameters.depthPrepass;
  state.apply();
  drawScene(scene, DrawSet::Opaque, nullptr, uniforms);
  state.depth = gl::DepthState{};
  state.depth.apply();
  drawScene(scene, DrawSet::Masked, nullptr, uniforms);
  // The beauty's background; the AOVs, layers, ids and debug views keep theirs empty.
  if (background) {
    drawBackground(targets, uniforms);
    state.apply();
    glBindVertexArray(scene.vertexArray());
  }
  // See-through surfaces over what the opaque and masked ones drew, which they read (the ids
  // pass has no beauty to read: they are opaque there).
  if (const SeeThrough seen = seeThrough(scene, camera.view); seen.any) {
    if (writesSrgb8(outputs_))
      throw std::logic_error("the 8-bit beauty pass cannot draw see-through surfaces");
    if (outputs_ != PassOutputs::Ids)
      drawSeeThrough(scene, seen, uniforms.viewProjection, targets, uniforms);
    else
      drawScene(scene, DrawSet::SeeThrough, nullptr, uniforms);
  }

  // Blended surfaces over the opaque frame, farthest first; the AOVs, layers and ids keep the
  // opaque surfaces (the ids take the blended ones' coverage alone).
  if (outputs_ == PassOutputs::Layers) {
    gl::RasterState::restoreDefaults();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gl::checkErrors("a layer pass");
    return;
  }
  state.depth.write = false;
  state.blend.buffers = 1u;  // premultiplied "over" into the beauty only
  state.blend.sourceColor = state.blend.sourceAlpha = GL_ONE;
  state.blend.destinationColor = state.blend.destinationAlpha = GL_ONE_MINUS_SRC_ALPHA;
  for (int i = 1; i < targets.attachmentCount(); ++i) state.color.offBuffers |= 1u << i;
  if (outputs_ == PassOutputs::Ids) state.color.rgba = {false, true, false, false};
  if (outputs_ == PassOutputs::BeautyIds) {  // the coverage of the ids, as the Ids pass blends it
    state.blend.buffers |= 2u;
    state.color.offBuffers &= ~2u;
    state.color.greenOnlyBuffers = 2u;
  }
  state.apply();
  drawScene(scene, DrawSet::Blended, nullptr, uniforms);
  gl::RasterState::restoreDefaults();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::checkErrors("the lighting pass");
}

void LightingPass::drawDepth(const GpuScene& scene, DrawSet set, const ShaderProgram& program,
                             const FrameUniforms& uniforms) {
  program.use();
  program.set("uViewProjection", uniforms.viewProjection);
  drawScene(scene, set, &program, uniforms);
}

AmbientOcclusionPass& LightingPass::occlusionPass() {
  if (!occlusion_) occlusion_ = std::make_unique<AmbientOcclusionPass>();
  return *occlusion_;
}

void LightingPass::estimateOcclusion(const GpuScene& scene, const ViewCamera& camera,
                                     const FrameTargets& targets, const PassParameters& parameters,
                                     const FrameUniforms& uniforms) {
  AmbientOcclusionPass& occlusion = occlusionPass();
  const int width = targets.width(), height = targets.height();
  GLuint depth = targets.depth();
  // Masked surfaces cast occlusion and take it too: where the frame has some, the estimate
  // draws its own depth of them and the opaque ones (the pre-pass draws no cut-outs).
  bool masked = false;
  for (const GpuDraw& draw : scene.draws())
    masked = masked || drawSet(draw.material, scene) == DrawSet::Masked;
  if (!parameters.depthPrepass || masked) {
    // The pre-pass's draws into a depth target of the estimate's own: the same depths, so the
    // picture does not depend on whether the pre-pass is drawn.
    const GLuint framebuffer = occlusion.depthFramebuffer(width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    gl::RasterState state;
    state.viewport = {0, 0, width, height};
    state.color.rgba = {false, false, false, false};
    state.apply();  // depth writes on: the clear obeys them
    const float clearDepth = 0.0f;
    glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &clearDepth);
    drawDepth(scene, DrawSet::Opaque, depthOnly_, uniforms);
    if (masked) {
      if (!maskedDepth_)
        maskedDepth_ = std::make_unique<ShaderProgram>("scene.vert", "depth_masked.frag",
                                                       contract::shaderContractDefines());
      drawDepth(scene, DrawSet::Masked, *maskedDepth_, uniforms);
    }
    depth = occlusion.depthTexture();
  }
  occlusion.estimate(depth, camera.projection, width, height, uniforms.ambience.occlusion->radius);
  bindOcclusion();
}

void LightingPass::bindOcclusion() const {
  const auto unit = static_cast<GLuint>(shadowUnits_.ambientOcclusion);
  glBindTextureUnit(unit, occlusion_->result());
  glBindSampler(unit, 0);
}

void LightingPass::drawBackground(const FrameTargets& targets, const FrameUniforms& uniforms) {
  if (!background_) {
    std::vector<std::string> defines = environmentUnitDefines(shadowUnits_.environment);
    if (writesSrgb8(outputs_)) defines.push_back("WRITE_SRGB8");
    background_ = std::make_unique<ShaderProgram>("fullscreen.vert", "environment_background.frag",
                                                  contract::withShaderContract(defines));
    if (writesSrgb8(outputs_)) {
      const std::array<float, 256>& steps = srgb8Steps();
      background_->set("uSrgb8Next", steps.data(), static_cast<int>(steps.size()));
    }
    emptyVertexArray_ = gl::createVertexArray();
  }
  const EnvironmentBinding& environment = uniforms.ambience.environment;
  background_->use();
  background_->set("uInverseViewProjection", glm::inverse(uniforms.viewProjection));
  background_->set("uViewportSize", glm::vec2(targets.width(), targets.height()));
  setEnvironmentUniforms(*background_, environment);
  if (writesSrgb8(outputs_)) background_->set("uExposureScale", uniforms.parameters.exposureScale);
  // The full-screen triangle lies at depth 0, the cleared value: it passes only where no
  // surface wrote a depth. The ids beside the beauty stay "none".
  gl::RasterState state;
  state.viewport = {0, 0, targets.width(), targets.height()};
  state.depth.func = GL_GEQUAL;
  state.depth.write = false;
  if (writesIdsBesideBeauty(outputs_)) state.color.offBuffers |= 2u;
  state.apply();
  // The picture takes the specular texture's unit for this draw; the surfaces drawn after it
  // read the specular texture there again.
  const auto unit = static_cast<GLuint>(shadowUnits_.environment);
  glBindTextureUnit(unit, environment.textures->background());
  glBindVertexArray(emptyVertexArray_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindTextureUnit(unit, environment.textures->specular());
}

bool depthPrepassSupported(std::string_view glRenderer) {
  return gl::isLlvmpipe(glRenderer);
}

OverdrawCounts LightingPass::estimateOpaqueFragments(const GpuScene& scene,
                                                     const std::vector<Mesh>& meshes,
                                                     const ViewCamera& camera) const {
  // 1280x720 at one sample per 8x8 pixels: within 1% of GL's occlusion counts on the bench
  // scenes, in 0.05-4.7 ms; the time goes per triangle (31 ms for 1M; docs/performance.md).
  constexpr int kMaxSamples = 16384;
  std::vector<OverdrawSurface> surfaces;
  for (const std::size_t index : nearestDrawOrder(scene, camera.view)) {
    const GpuDraw& draw = scene.draws()[index];
    const GpuMaterial& material = scene.materials()[draw.material];
    if (drawSetOf(materialVariant(material), material) != DrawSet::Opaque ||
        !drawnInSet(draw, DrawSet::Opaque))
      continue;
    surfaces.push_back({&meshes.at(static_cast<std::size_t>(draw.mesh)), draw.world,
                        !material.desc.doubleSided, draw.mirrored});
  }
  return estimateOverdraw(surfaces, camera.projection * camera.view, camera.width, camera.height,
                          kMaxSamples);
}

}  // namespace omnishadow
