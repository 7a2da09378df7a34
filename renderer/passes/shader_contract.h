#pragma once

// The contract between the passes and their shaders: texture units, buffer bindings, array
// limits, enum values and the std430 layouts both sides read. C++ is the only place these
// numbers are written. shaderContractDefines() hands them to every program of the passes as
// preprocessor macros, so a shader says `layout(binding = BASE_COLOR_UNIT)` and can never
// drift from the unit the C++ side binds. GL-free on purpose: tests and planning code may check
// the limits without a context.

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "renderer/render/render_settings.h"
#include "renderer/scene/light.h"
#include "renderer/view/shadow_plan.h"
#include "renderer/view/sheen_brdf.h"

namespace omnishadow::contract {

// Material textures of the lighting pass, one unit per glTF texture slot.
inline constexpr int kBaseColorUnit = 0;
inline constexpr int kMetallicRoughnessUnit = 1;
inline constexpr int kNormalUnit = 2;
inline constexpr int kOcclusionUnit = 3;
inline constexpr int kEmissiveUnit = 4;
inline constexpr int kMaterialUnits = 5;

// The textures of shadow_transmittance.frag besides the base color (its own program: any free
// units).
inline constexpr int kTransmissionUnit = kBaseColorUnit + 1;
inline constexpr int kShadowThicknessUnit = kBaseColorUnit + 2;
inline constexpr int kShadowDiffuseTransmissionUnit = kBaseColorUnit + 3;
inline constexpr int kShadowDiffuseTransmissionColorUnit = kBaseColorUnit + 4;

// The moments layer the VSM blur reads (its own program, so it may reuse unit 0).
inline constexpr int kVsmSourceUnit = 0;

// The frame's transmittance atlas of translucent shadows (transmittance_pass.h), one 2D array
// for every light, and the rectangle each atlas layer holds (a buffer texture).
inline constexpr int kTransmittanceUnit = kMaterialUnits;
inline constexpr int kTransmittanceRectsUnit = kTransmittanceUnit + 1;
// Shadow sampler arrays follow. Only the families the frame's filters read are declared
// (compare, raw depth, moments; cube and planar), each with as many units as the frame has
// shadow groups of a layout (renderer/passes/lighting_pass.cpp, shadowSamplerUnits), so that a
// frame of one filter takes one or two units, not 24.
inline constexpr int kMaxShadowGroups = omnishadow::kMaxShadowGroups;
inline constexpr int kFirstShadowUnit = kTransmittanceRectsUnit + 1;
inline constexpr int kShadowSamplerFamilies = 6;
// llvmpipe (and most desktop drivers) offer 32 fragment units; more would fail only at link.
inline constexpr int kTextureUnits = 32;
static_assert(kFirstShadowUnit + kShadowSamplerFamilies * kMaxShadowGroups <= kTextureUnits,
              "shadow units beyond 32");

// The material extensions' textures. A variant of the lighting shader gives those it reads the
// units after the frame's shadow arrays, one each in this order (lighting_pass.cpp,
// extensionTextureUnits), and declares them with these defines; a variant whose textures would
// reach past the last unit draws those extensions from their factors (see-through surfaces as
// their base material).
enum class ExtensionTexture : int {
  Sheen,                     // KHR_materials_sheen: the color (RGB, sRGB) and, of the same image, A
  SheenRoughness,            // its roughness texture when another image (A)
  Clearcoat,                 // KHR_materials_clearcoat: the layer's intensity (R)
  ClearcoatRoughness,        // its roughness (G)
  ClearcoatNormal,           // its normals
  Specular,                  // KHR_materials_specular: the factor (A)
  SpecularColor,             // and the color (RGB, sRGB)
  Transmission,              // KHR_materials_transmission (R)
  SceneBehind,               // what a frame drew behind its see-through surfaces (LightingPass)
  Thickness,                 // KHR_materials_volume (G)
  Anisotropy,                // KHR_materials_anisotropy (RG direction, B strength)
  Iridescence,               // KHR_materials_iridescence: the strength (R)
  IridescenceThickness,      // and the film's thickness (G)
  DiffuseTransmission,       // KHR_materials_diffuse_transmission: the fraction (A)
  DiffuseTransmissionColor,  // and the color (RGB, sRGB)
};
inline constexpr int kExtensionTextures = 15;
inline constexpr const char* kExtensionTextureUnitDefines[kExtensionTextures] = {
    "SHEEN_UNIT",
    "SHEEN_ROUGHNESS_UNIT",
    "CLEARCOAT_UNIT",
    "CLEARCOAT_ROUGHNESS_UNIT",
    "CLEARCOAT_NORMAL_UNIT",
    "SPECULAR_UNIT",
    "SPECULAR_COLOR_UNIT",
    "SURFACE_TRANSMISSION_UNIT",
    "SCENE_BEHIND_UNIT",
    "THICKNESS_UNIT",
    "ANISOTROPY_UNIT",
    "IRIDESCENCE_UNIT",
    "IRIDESCENCE_THICKNESS_UNIT",
    "DIFFUSE_TRANSMISSION_UNIT",
    "DIFFUSE_TRANSMISSION_COLOR_UNIT"};

// Shader storage buffer bindings. Models and DrawObjects are the shadow pass's
// (shaders/shadow_depth.vert); the rest are the lighting pass's. Unscoped: they are the ints
// glBindBufferBase and the shader defines take.
enum StorageBinding : int {
  kLightsBinding = 0,
  kModelsBinding = 1,
  kDrawObjectsBinding = 2,
  kShadowViewProjectionsBinding = 3,
  kClusterRangesBinding = 4,
  kClusterLightsBinding = 5,
};

// Uniform buffer bindings (a namespace of their own in GL). The lighting pass reads its lights
// and their shadow view-projections from uniform blocks while they fit the smallest block every
// GL 4.x offers, and from the storage buffers above beyond that: llvmpipe loads a storage
// buffer one lane at a time, a uniform block with one vector gather, so per pixel and light the
// uniform block is the cheaper read.
enum UniformBinding : int {
  kLightsUniformBinding = 0,
  kShadowViewProjectionsUniformBinding = 1,
  kLayerViewProjectionsUniformBinding = 2,  // the batched shadow pass's, per texture layer
};
inline constexpr int kMinUniformBlockBytes = 16384;  // GL_MAX_UNIFORM_BLOCK_SIZE's minimum
inline constexpr int kMaxUniformLights = kMinUniformBlockBytes / (10 * 16);          // GpuLight
inline constexpr int kMaxUniformViewProjections = kMinUniformBlockBytes / (16 * 4);  // mat4

// The AOV pass reports the shadow terms of up to 4 lights per RGBA target, in at most this many
// targets (VISIBILITY_OUTPUTS, a variant define: LightingFeatures::visibilityOutputs).
inline constexpr int kMaxVisibilityOutputs = 5;

// A directional light's cascade ends and texel sizes travel as one vec4 each.
inline constexpr int kMaxCascades = 4;
static_assert(std::tuple_size_v<decltype(LightShadowPlan::cascadeEnd)> == kMaxCascades &&
                  std::tuple_size_v<decltype(LightShadowPlan::cascadeTexel)> == kMaxCascades,
              "GpuLight::cascadeEnd/cascadeTexel hold one vec4 of cascades");

// std430 and std140 mirror of `Light` in shaders/lights.glsl: only vec4 members, so C++, std430
// and std140 agree on every offset as long as each stays a multiple of 16. The shader indexes
// lights by this stride; the asserts below break the build before a reordering breaks the picture.
struct GpuLight {
  glm::vec4 positionRange;     // world position, range (0 = unlimited)
  glm::vec4 directionType;     // direction the light travels, LightType
  glm::vec4 radianceShadow;    // color * intensity, shadow group slot (-1 = unshadowed)
  glm::vec4 spotFilter;        // cone scale, cone offset, ShadowFilter, shadow resolution
  glm::vec4 shadowDepth;       // near, far, constant bias (world), slope bias (texels)
  glm::vec4 shadowBias;        // min bias (texels), normal bias (texels), filter radius, samples
  glm::vec4 shadowSoft;        // source radius, vsm bleed reduction, first layer, layer count
  glm::vec4 shadowProjection;  // spot: tan(half fov); first entry in the view projections;
                               // translucent shadows: 1 + a bit per shadow layer with atlas
                               // layers (0: none), the first of them
  glm::vec4 cascadeEnd;        // directional: camera view depth where each cascade ends
  glm::vec4 cascadeTexel;      // directional: world size of a texel in each cascade
};
static_assert(sizeof(glm::vec4) == 16 && alignof(glm::vec4) <= 16, "glm::vec4 is not a vec4");
static_assert(sizeof(GpuLight) == 10 * 16, "GpuLight must match the std430 layout of Light");
static_assert(kMaxUniformLights * sizeof(GpuLight) <= kMinUniformBlockBytes);
static_assert(sizeof(GpuLight) % 16 == 0, "std430 arrays of Light have a 16-byte stride");
static_assert(offsetof(GpuLight, positionRange) == 0 * 16);
static_assert(offsetof(GpuLight, directionType) == 1 * 16);
static_assert(offsetof(GpuLight, radianceShadow) == 2 * 16);
static_assert(offsetof(GpuLight, spotFilter) == 3 * 16);
static_assert(offsetof(GpuLight, shadowDepth) == 4 * 16);
static_assert(offsetof(GpuLight, shadowBias) == 5 * 16);
static_assert(offsetof(GpuLight, shadowSoft) == 6 * 16);
static_assert(offsetof(GpuLight, shadowProjection) == 7 * 16);
static_assert(offsetof(GpuLight, cascadeEnd) == 8 * 16);
static_assert(offsetof(GpuLight, cascadeTexel) == 9 * 16);

// ShadowViewProjections (shaders/lights.glsl) and Models (shaders/shadow_depth.vert) are std430
// arrays of mat4: a 64-byte stride, column-major like glm.
static_assert(sizeof(glm::mat4) == 64 && sizeof(glm::mat4) % 16 == 0,
              "glm::mat4 must match a std430 mat4");

// ClusterRanges and ClusterLights (shaders/lighting.frag) are std430 arrays of uint: ranges as
// (first, count) pairs, then light indices.
using GpuClusterIndex = std::uint32_t;
static_assert(sizeof(GpuClusterIndex) == 4, "a GLSL uint is 4 bytes");

// The numbers above as "NAME VALUE" entries for ShaderProgram's defines, plus the enum values
// the shaders compare against (LIGHT_*, FILTER_*, DEBUG_VIEW_*).
inline std::vector<std::string> shaderContractDefines() {
  const auto define = [](const char* name, int value) {
    return std::string(name) + " " + std::to_string(value);
  };
  const auto e = [](auto value) { return static_cast<int>(value); };
  return {
      define("BASE_COLOR_UNIT", kBaseColorUnit),
      define("METALLIC_ROUGHNESS_UNIT", kMetallicRoughnessUnit),
      define("NORMAL_UNIT", kNormalUnit),
      define("OCCLUSION_UNIT", kOcclusionUnit),
      define("EMISSIVE_UNIT", kEmissiveUnit),
      define("SHEEN_ALBEDO_COSINES", kSheenAlbedoCosines),
      define("SHEEN_ALBEDO_ROUGHNESSES", kSheenAlbedoRoughnesses),
      "MIN_SHEEN_ALPHA " + std::to_string(kMinSheenAlpha),
      define("TRANSMISSION_UNIT", kTransmissionUnit),
      define("SHADOW_THICKNESS_UNIT", kShadowThicknessUnit),
      define("SHADOW_DIFFUSE_TRANSMISSION_UNIT", kShadowDiffuseTransmissionUnit),
      define("SHADOW_DIFFUSE_TRANSMISSION_COLOR_UNIT", kShadowDiffuseTransmissionColorUnit),
      define("VSM_SOURCE_UNIT", kVsmSourceUnit),
      define("MAX_SHADOW_GROUPS", kMaxShadowGroups),
      define("TRANSMITTANCE_UNIT", kTransmittanceUnit),
      define("TRANSMITTANCE_RECTS_UNIT", kTransmittanceRectsUnit),
      define("LIGHTS_BINDING", kLightsBinding),
      define("MODELS_BINDING", kModelsBinding),
      define("DRAW_OBJECTS_BINDING", kDrawObjectsBinding),
      define("SHADOW_VIEW_PROJECTIONS_BINDING", kShadowViewProjectionsBinding),
      define("CLUSTER_RANGES_BINDING", kClusterRangesBinding),
      define("CLUSTER_LIGHTS_BINDING", kClusterLightsBinding),
      define("LIGHTS_UNIFORM_BINDING", kLightsUniformBinding),
      define("SHADOW_VIEW_PROJECTIONS_UNIFORM_BINDING", kShadowViewProjectionsUniformBinding),
      define("LAYER_VIEW_PROJECTIONS_UNIFORM_BINDING", kLayerViewProjectionsUniformBinding),
      define("MAX_UNIFORM_LIGHTS", kMaxUniformLights),
      define("MAX_UNIFORM_VIEW_PROJECTIONS", kMaxUniformViewProjections),
      define("LIGHT_POINT", e(LightType::Point)),
      define("LIGHT_SPOT", e(LightType::Spot)),
      define("LIGHT_DIRECTIONAL", e(LightType::Directional)),
      define("FILTER_HARD", e(ShadowFilter::Hard)),
      define("FILTER_PCF", e(ShadowFilter::Pcf)),
      define("FILTER_PCF_DISK", e(ShadowFilter::PcfDisk)),
      define("FILTER_POISSON", e(ShadowFilter::Poisson)),
      define("FILTER_PCSS", e(ShadowFilter::Pcss)),
      define("FILTER_VSM", e(ShadowFilter::Vsm)),
      define("DEBUG_VIEW_NONE", e(DebugView::None)),
      define("DEBUG_VIEW_SHADOW", e(DebugView::Shadow)),
      define("DEBUG_VIEW_DEPTH", e(DebugView::Depth)),
      define("DEBUG_VIEW_NORMALS", e(DebugView::Normals)),
      define("DEBUG_VIEW_ALBEDO", e(DebugView::Albedo)),
      define("DEBUG_VIEW_LIGHT_COUNT", e(DebugView::LightCount)),
      define("DEBUG_VIEW_CASCADE", e(DebugView::Cascade)),
      define("DEBUG_VIEW_OCCLUSION", e(DebugView::Occlusion)),
  };
}

// A program's own variant defines followed by the contract.
inline std::vector<std::string> withShaderContract(std::vector<std::string> defines) {
  for (std::string& define : shaderContractDefines()) defines.push_back(std::move(define));
  return defines;
}

}  // namespace omnishadow::contract
