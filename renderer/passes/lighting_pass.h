#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "renderer/gl/gl_resources.h"
#include "renderer/gl/shader_program.h"
#include "renderer/passes/ambient_occlusion_pass.h"
#include "renderer/passes/environment_textures.h"
#include "renderer/passes/gpu_scene.h"
#include "renderer/passes/shader_contract.h"
#include "renderer/passes/shadow_textures.h"
#include "renderer/passes/transmittance_pass.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/light.h"
#include "renderer/view/camera.h"
#include "renderer/view/caster_culling.h"
#include "renderer/view/light_clusters.h"
#include "renderer/view/overdraw_estimate.h"
#include "renderer/view/texel_region.h"

namespace omnishadow {

// Which render targets a lighting pass variant writes besides the beauty.
enum class PassOutputs {
  Beauty,  // attachment 0 only
  // Attachment 0 only, RGBA8UI: the beauty times 2^exposure as the 8-bit sRGB bytes toSrgb8()
  // makes of the float one (shaders/srgb8_encode.glsl). A quarter of the float target's bytes
  // to clear and read back; it cannot blend, so only for frames without blended surfaces.
  Srgb8,
  // Srgb8, and attachment 1, R32F: the objectId as Ids writes it (masks of a frame without
  // blended surfaces): the ids come with the beauty's draws instead of a pass of their own.
  Srgb8Ids,
  // Beauty, and attachment 1 as Ids writes it, its coverage blended over as there: the ids of
  // masks come with the beauty's draws (a pixel only blended surfaces cover still takes the id
  // of the front-most one from the Ids pass).
  BeautyIds,
  Aovs,    // + position/distance, normal, visibility of up to 20 lights
  Layers,  // + two layer targets: material layers or one light's diffuse and specular
  // Attachment 0 only, RG32F: the surface's objectId (R; -1 = none) and its coverage (G:
  // blended surfaces blended over the opaque ones as into the beauty's A, their ids left
  // out). No material or light beyond the base color's alpha.
  Ids,
};

// Whether the pass shades a beauty (its ambient and environment light screen-space occluded
// when the frame asks): not the layer and id passes.
inline bool readsAmbientOcclusion(PassOutputs outputs) {
  return outputs != PassOutputs::Layers && outputs != PassOutputs::Ids;
}

// Ids in attachment 1 beside the beauty (Srgb8Ids, BeautyIds).
inline bool writesIdsBesideBeauty(PassOutputs outputs) {
  return outputs == PassOutputs::Srgb8Ids || outputs == PassOutputs::BeautyIds;
}

// The beauty as 8-bit sRGB codes in attachment 0 (Srgb8, Srgb8Ids).
inline bool writesSrgb8(PassOutputs outputs) {
  return outputs == PassOutputs::Srgb8 || outputs == PassOutputs::Srgb8Ids;
}

// What lights a lighting pass's surfaces besides its lights: the constant ambient radiance and
// the environment light (its textures null: none).
struct LightingAmbience {
  glm::vec3 ambient{0.0f};
  EnvironmentBinding environment;
  // Screen-space occlusion of both (its radius resolved: > 0), for passes made with
  // LightingFeatures::ambientOcclusion.
  std::optional<AmbientOcclusion> occlusion;
};

// Per-pass choices of a lighting pass.
struct PassParameters {
  int visibilityBase = 0;  // Aovs: first light whose shadow term goes to the visibility targets
  DebugView debugView = DebugView::None;
  int debugLight = -1;  // DebugView::Depth: index of the shadowed point light shown
  int layerMode = 0;    // Layers: 0 = albedo/roughness/metallic/ids, 1 = one light's split
  int layerLight = -1;  // Layers, mode 1: the light
  // Directional cascades were fitted to this camera; null = the camera being drawn.
  const glm::mat4* cascadeView = nullptr;
  // Aovs, Layers, Ids: draw only the blended surfaces, the front-most one per pixel, unblended
  // (the AOVs of pixels no opaque surface covers, renderer.cpp).
  bool blendedOnly = false;
  // Aovs: the visibility targets' channels from 0 hold the scalar shadow terms of
  // `scalarTerms` lights from visibilityBase on; from channel `rgbFirst` on (-1: none), the RGB
  // terms (translucent shadows: the transmittance.<light> AOVs) of those lights, R, G, B of each
  // in turn, as many as fit (AovVisibilityLayout).
  int scalarTerms = 0;
  int rgbFirst = -1;
  float exposureScale = 1.0f;  // Srgb8: 2^exposure
  // Opaque surfaces first write their depth alone, then shade where theirs is the nearest
  // (each pixel shaded once); without it they test and write depth as they shade (some
  // pixels shaded several times, no second pass over the triangles). The picture is the same:
  // the nearest surface, the last drawn of equally near ones.
  bool depthPrepass = true;
  // Aovs: this pass draws the frame the pass before it drew (camera, geometry, size), so it
  // reads the ambient occlusion estimate that pass made rather than making it again.
  bool reuseOcclusion = false;
};

// Whether the beauty's depth pre-pass is drawn at all on a GL renderer (its GL_RENDERER
// string): on llvmpipe, where shading costs more than drawing the triangles again and the
// pre-pass was measured to pay; not on GPUs, whose early depth tests spare most of that work,
// and where NVIDIA's driver (580.159, H100) lost blocks of WhackAMole's ground with it (the
// shading pass's GL_GEQUAL failing against the pre-pass's depths; docs/performance.md).
bool depthPrepassSupported(std::string_view glRenderer);

// How the AOV passes of a frame report its lights' shadow terms in their visibility targets:
// the scalar terms one light per channel, the RGB terms of translucent shadows (`rgbTerms`)
// three channels per light, in passes of their own or, for up to kMaxCombinedLights lights,
// after the scalar terms in the same pass. As few targets as that takes, up to
// contract::kMaxVisibilityOutputs: each is one more to clear and write for every pixel (a
// one-light frame's AOV pass took 35 ms with five, 21 with one), and each pass draws the scene.
struct AovVisibilityLayout {
  int outputs = 1;        // visibility targets
  int scalarPerPass = 4;  // lights whose scalar terms one pass reports
  int rgbPerPass = 0;     // lights whose RGB terms one pass reports
  bool combined = false;  // one pass: the RGB terms from channel scalarPerPass on
};
inline constexpr int kMaxCombinedLights = 4;
AovVisibilityLayout aovVisibilityLayout(int lights, bool rgbTerms);
// A light as the lighting pass sees it: its description plus where its shadow map is.
struct ShadedLight {
  const Light* light = nullptr;
  const LightShadowPlan* shadow = nullptr;  // null = unshadowed
  bool translucent = false;                 // translucent casters tint its shadow
  // Where those casters were drawn in the transmittance atlas (transmittance_pass.h); shadow
  // layers without atlas layers are untinted.
  int transmittanceFirst = 0;
  unsigned transmittanceLayers = 0u;
};

// The frame's shadow textures, indexed like ShadowAtlasPlan::groups.
using ShadowGroups = std::vector<ShadowGroupTextures>;

// Render targets of one frame, RGBA32F each (Srgb8: RGBA8UI): 0 is linear premultiplied RGBA
// (Srgb8: its sRGB bytes); for Aovs also 1: world position + camera distance, 2: camera-facing
// normal, 3 on: `visibilityOutputs` targets of 4 lights' visibility; for Layers 1 and 2 hold the
// layer values.
class FrameTargets {
 public:
  // `madeZeroed`: the driver fills every texture it makes with zero bytes, as llvmpipe does
  // (ShadowTexturePool), so new targets hold what a pass that clears to zeros clears them to.
  // `zerosByUpload`: the driver's textures live in this process's memory and an upload copies
  // them a row at a time, as llvmpipe's do, whose clears write a 16-byte texel at a time: the
  // float attachments that clear to zeros take them from memory (uploadZeros()).
  FrameTargets(int width, int height, PassOutputs outputs,
               int visibilityOutputs = contract::kMaxVisibilityOutputs, bool madeZeroed = false,
               bool zerosByUpload = false);
  // The most bytes such targets take (their colors and a 32-bit depth), for checks made before
  // any of them is allocated.
  static double bytes(int width, int height, PassOutputs outputs);
  GLuint framebuffer() const { return framebuffer_.get(); }
  GLuint color(int attachment) const { return colors_[attachment].get(); }
  GLuint depth() const { return depth_.get(); }
  int attachmentCount() const { return static_cast<int>(colors_.size()); }
  int visibilityOutputs() const { return visibilityOutputs_; }  // Aovs; 0 for the others
  PassOutputs outputs() const { return outputs_; }
  int width() const { return width_; }
  int height() const { return height_; }

  // The pixels a pass that clears to `clearValues` (a key of the values it clears to; `zeros`:
  // they are all zero bytes) must clear: those the last pass may have drawn, where the rest
  // still hold what it cleared them to; every pixel before other clear values, and of new
  // targets unless they were made zeroed and the values are zeros. llvmpipe clears a 16-byte
  // texel at a time and visits every tile a clear reaches: a whole 1280x720 float beauty took
  // 2.2 ms of Sundial's 10 ms lighting pass.
  TexelRegion toClear(int clearValues, bool zeros) const;
  // A pass cleared toClear() to `clearValues` and then drew within `drawn`.
  void cleared(int clearValues, const TexelRegion& drawn);
  // The pixels the last pass may have drawn: every other pixel holds what it cleared them to.
  // The whole frame before any pass has cleared.
  TexelRegion drawn() const {
    return clearValues_ ? drawn_ : TexelRegion(TexelRect::whole(width_, height_));
  }

  bool zerosByUpload() const { return zerosByUpload_; }
  // Zero bytes into the texels of `region` of color attachment `attachment` (RGBA32F), uploaded
  // from memory of zeros a rectangle at a time. On llvmpipe, Sundial's steady lighting pass
  // 10.8 -> 10.0 ms against a scissored clear of the region's bounds (docs/performance.md).
  void uploadZeros(int attachment, const TexelRegion& region);

 private:
  int width_, height_;
  PassOutputs outputs_;
  int visibilityOutputs_;
  bool madeZeroed_;
  bool zerosByUpload_;
  std::vector<float> zeros_;        // for the largest rectangle uploadZeros() has written
  std::optional<int> clearValues_;  // none: nothing cleared them yet
  TexelRegion drawn_;
  gl::Framebuffer framebuffer_;
  std::vector<gl::Texture> colors_;
  gl::Texture depth_;
};

// What a lighting pass variant is compiled for besides its outputs: the shadow layouts and
// filters present in the frame, and the depth debug view. Absent features compile out.
struct LightingFeatures {
  bool cubeShadows = false;
  bool planarShadows = false;
  // The slots of the shader's shadow sampler arrays: the frame's shadow groups of the layout
  // that has more of them (at most kMaxShadowGroups; set from the frame's shadow atlas plan).
  // llvmpipe compiles the texture code once per slot of an array indexed at run time, so arrays
  // sized to the frame compile faster on a cold shader cache.
  int shadowSlots = 0;
  unsigned filters = 0;     // bit per ShadowFilter
  bool debugViews = false;  // a --debug-view picture: DEBUG_VIEWS
  bool debugDepth = false;
  bool translucentShadows = false;  // some light samples transmittance layers
  // Some light has a range: fragments loop over their cluster's lights, not over all of them.
  bool clusteredLights = false;
  // The light types present: incidentLight() leaves out the cone or the directional case of a
  // frame without them (llvmpipe would run both sides of the branch in every fragment).
  bool spotLights = false;
  bool directionalLights = false;
  // More lights (or planar shadow view-projections) than the uniform blocks hold: the lights
  // are read from storage buffers (shader_contract.h).
  bool lightsInStorage = false;
  // At most kMaxFacingLoopLights lights, none with a range, and a GL with GL_ARB_shader_ballot
  // (lightingFeatures() leaves that to the caller): the beauty's light loop visits only the
  // lights some pixel of each lane group faces (shaders/lighting.frag, FACING_LIGHT_LOOP).
  bool facingLightLoop = false;
  // Aovs: the visibility targets (AovVisibilityLayout::outputs); 0 for the other outputs.
  int visibilityOutputs = 0;
  // An environment light: its textures take three units after the shadow arrays.
  bool environment = false;
  // Screen-space ambient occlusion (LightingAmbience::occlusion): the passes that write a
  // beauty estimate it from the opaque and masked surfaces' depth and read it on the unit after
  // those.
  bool ambientOcclusion = false;
  bool operator==(const LightingFeatures&) const = default;
};

// The facing-light loop keeps its lights in a 32-bit mask.
inline constexpr std::size_t kMaxFacingLoopLights = 32;

LightingFeatures lightingFeatures(const std::vector<Light>& lights, DebugView debugView);

// The first texture unit of each shadow sampler array the lighting pass declares for a frame
// with `features` (-1: not declared, the frame's filters never read it), each array
// SHADOW_SLOTS units long, then the environment's. The material extensions' textures take the
// units from `end` on.
struct ShadowSamplerUnits {
  int cubeCompare = -1, planarCompare = -1, cubeDepth = -1, planarDepth = -1, cubeMoments = -1,
      planarMoments = -1;
  int environment = -1;       // LightingFeatures::environment: specular, irradiance, BRDF table
  int ambientOcclusion = -1;  // LightingFeatures::ambientOcclusion
  int end = 0;                // one past the last unit taken
};
ShadowSamplerUnits shadowSamplerUnits(const LightingFeatures& features);

// Sets the shadow slots of `features` from the frame's atlas.
void setShadowSlots(const ShadowAtlasPlan& atlas, LightingFeatures& features);

class LightingPass {
 public:
  LightingPass(Shading shading, PassOutputs outputs, const LightingFeatures& features);

  // Compiles the material variants the scene's draws use (the pass compiles any missing one
  // when it first draws with it).
  void compileMaterialVariants(const GpuScene& scene);

  // Draws opaque and masked surfaces, then see-through ones (KHR_materials_transmission, over a
  // copy of what the others drew), then blended ones (farthest first, depth writes off, AOV
  // targets untouched); layer passes draw no blended surfaces.
  void render(const GpuScene& scene, const ViewCamera& camera,
              const std::vector<ShadedLight>& lights, const ShadowGroups& shadowGroups,
              const TransmittanceAtlas& transmittanceAtlas, const LightingAmbience& ambience,
              FrameTargets& targets, const PassParameters& parameters);

  // The opaque fragments of `camera`'s frame with and without the depth pre-pass, estimated on
  // the CPU before anything is drawn (estimateOverdraw(), at most 16,384 samples): the opaque
  // surfaces this pass shades, in its order, with their culling. `meshes`: the scene's, which
  // `scene` was made from.
  OverdrawCounts estimateOpaqueFragments(const GpuScene& scene, const std::vector<Mesh>& meshes,
                                         const ViewCamera& camera) const;

 private:
  // The frame's uniforms, the same in every material variant.
  struct FrameUniforms {
    glm::mat4 viewProjection{1.0f}, cameraView{1.0f};
    glm::vec3 cameraPosition{0.0f};
    LightingAmbience ambience;
    glm::vec4 viewDepth{0.0f};
    int lightCount = 0;
    LightClusters clusters;  // the grid the cluster buffers were built for
    PassParameters parameters;
  };
  int uploadLights(const std::vector<ShadedLight>& lights, const ShadowGroups& shadowGroups,
                   const TransmittanceAtlas& transmittanceAtlas);
  // Uploads `items` (a frame's lights or view-projections) and binds them where this variant's
  // shader reads them: the storage binding, or the uniform block padded to its declared size.
  template <typename T>
  void bindLightBlock(gl::StreamBuffer& buffer, std::vector<T>& items, int storageBinding,
                      int uniformBinding, std::size_t uniformCapacity) const;
  void uploadClusters(const GpuScene& scene, const std::vector<ShadedLight>& lights,
                      const ViewCamera& camera, FrameUniforms& uniforms);
  void setFrameUniforms(const ShaderProgram& program, const FrameUniforms& uniforms) const;
  // Material variant: a bit per texture slot the material has (in unit order), then one for
  // specular-glossiness. llvmpipe runs both sides of every branch, so the shader leaves out
  // the texture reads and BRDFs the material cannot use.
  unsigned materialVariant(const GpuMaterial& material) const;
  const ShaderProgram& program(unsigned variant);
  // Opaque and masked draws, those drawn see-through after them, and blended ones.
  enum class DrawSet { Opaque, Masked, SeeThrough, Blended };
  // The set of the draws of scene material `material`, from this frame's variants.
  DrawSet drawSet(std::size_t material, const GpuScene& scene) const;
  // The same for a material of `variant` (materialVariant()).
  static DrawSet drawSetOf(unsigned variant, const GpuMaterial& material);
  // Whether `draw` of `set` is drawn, or left to a copy of it (GpuDraw::repeatedLater).
  static bool drawnInSet(const GpuDraw& draw, DrawSet set);
  struct SeeThrough {
    bool any = false;      // some draw is drawn see-through
    bool blurred = false;  // and some of those may read a coarser level (rough, ior above 1)
    std::vector<std::size_t> order;  // the see-through draws, farthest from the camera first
  };
  SeeThrough seeThrough(const GpuScene& scene, const glm::mat4& view) const;
  // Draws the see-through surfaces farthest first, each over a copy of what lies behind it:
  // one copy for all of them, and another before each whose screen bounds meet those of one
  // drawn since the last copy, so that see-through surfaces show each other; a thin-walled
  // double-sided mesh that is not flat draws its back faces, is copied, then its front faces.
  void drawSeeThrough(const GpuScene& scene, const SeeThrough& seen,
                      const glm::mat4& viewProjection, const FrameTargets& targets,
                      const FrameUniforms& uniforms);
  // What color attachment `attachment` holds where no surface is.
  std::array<float, 4> clearValue(int attachment, const PassParameters& parameters) const;
  // Clears the color targets to their clearValue() and the depth, within the scissor; the float
  // attachments that clear to zeros take them by upload over `zerosOver` instead where it is
  // given (FrameTargets::uploadZeros()).
  void clearTargets(FrameTargets& targets, const PassParameters& parameters,
                    const TexelRegion* zerosOver = nullptr) const;
  // The environment where no surface covers a pixel (EnvironmentBinding::background), over
  // the opaque and masked surfaces' depth and under what is drawn after them.
  // Leaves its own raster state applied.
  void drawBackground(const FrameTargets& targets, const FrameUniforms& uniforms);
  // The screen-space ambient occlusion of the opaque and masked surfaces
  // (LightingAmbience::occlusion), from the pre-pass's depth or, without it or with masked
  // surfaces, from the same draws (and the masked ones') into the estimate's own depth target,
  // bound where the shader reads it. Leaves the framebuffer and vertex array
  // changed.
  void estimateOcclusion(const GpuScene& scene, const ViewCamera& camera,
                         const FrameTargets& targets, const PassParameters& parameters,
                         const FrameUniforms& uniforms);
  // Binds occlusion_'s result where the shader reads it.
  void bindOcclusion() const;
  AmbientOcclusionPass& occlusionPass();  // occlusion_, made on first use
  // Whether this variant reads the screen-space occlusion: the frame has it and the pass
  // shades a beauty.
  bool readsOcclusion() const {
    return features_.ambientOcclusion && readsAmbientOcclusion(outputs_);
  }
  // The depth alone of `set`'s surfaces, drawn with `program` (depthOnly_, or the masked
  // surfaces' alpha-tested one) at the frame's view-projection.
  void drawDepth(const GpuScene& scene, DrawSet set, const ShaderProgram& program,
                 const FrameUniforms& uniforms);
  // Copies the beauty drawn so far (the opaque and masked surfaces) into sceneBehind_, with its
  // mipmaps when `mipmaps`, and binds it where see-through surfaces read it.
  void copySceneBehind(const FrameTargets& targets, bool mipmaps);
  // depthOnly: that program for every draw; null: each material's lighting variant, whose
  // frame uniforms `uniforms` sets on first use. Blended draws go in blendedOrder_, a double-sided
  // one as two draws: back faces, then front faces; the others in nearestOrder_.
  // `only`: just these draws of `set`, in this order (null: all of the set's). `faces`: GL_FRONT
  // or GL_BACK to draw only those faces (GL_FRONT_AND_BACK: as the material says).
  void drawScene(const GpuScene& scene, DrawSet set, const ShaderProgram* depthOnly,
                 const FrameUniforms& uniforms, const std::vector<std::size_t>* only = nullptr,
                 GLenum faces = GL_FRONT_AND_BACK);
  void drawPointsAndLines(const GpuMeshRange& range, const ShaderProgram& program, bool lighting);

  Shading shading_;
  PassOutputs outputs_;
  LightingFeatures features_;
  ShadowSamplerUnits shadowUnits_;
  std::vector<std::pair<unsigned, std::unique_ptr<ShaderProgram>>> programs_;
  std::vector<unsigned> framePrograms_;  // the variants holding this frame's uniforms
  // materialVariant() of each scene material, worked out once per render() (every draw of
  // every draw set reads it).
  std::vector<unsigned> frameVariants_;
  std::vector<std::size_t> blendedOrder_;  // this frame's blended draws, farthest first
  std::vector<std::size_t> nearestOrder_;  // this frame's draws, nearest first
  ShaderProgram depthOnly_;
  std::unique_ptr<ShaderProgram> background_;        // drawBackground()'s, made on first use
  std::unique_ptr<AmbientOcclusionPass> occlusion_;  // occlusionPass()
  std::unique_ptr<ShaderProgram> maskedDepth_;       // masked surfaces' depth for it, likewise
  gl::VertexArray emptyVertexArray_;                 // its full-screen triangle needs no attributes
  // occlusion_ holds this pass's last estimate, not a clear: a pass with reuseOcclusion reads it.
  bool occlusionEstimated_ = false;
  gl::Sampler cubeCompare_, planarCompare_, rawDepth_, moments_;
  gl::StreamBuffer lightBuffer_, viewProjectionBuffer_, clusterRanges_, clusterLights_;
  ClusterBoxCache clusterBoxes_;
  gl::Texture sceneBehind_;  // copySceneBehind(), RGBA16F with mipmaps, kept while the size is
  gl::Framebuffer behindFramebuffer_;
  int behindWidth_ = 0, behindHeight_ = 0;
};

}  // namespace omnishadow
