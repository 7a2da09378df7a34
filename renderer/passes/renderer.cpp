#include "renderer/render/renderer.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "renderer/core/errors.h"
#include "renderer/core/in_parts.h"
#include "renderer/gl/context_defaults.h"
#include "renderer/gl/egl_context.h"
#include "renderer/gl/gl_debug.h"
#include "renderer/gl/software_rasterizer.h"
#include "renderer/passes/attachment_readback.h"
#include "renderer/passes/gpu_scene.h"
#include "renderer/passes/lighting_pass.h"
#include "renderer/passes/shadow_pass.h"
#include "renderer/passes/shadow_textures.h"
#include "renderer/passes/shadow_worker.h"
#include "renderer/passes/srgb8_band_encoding.h"
#include "renderer/passes/srgb8_resolve.h"
#include "renderer/passes/transmittance_pass.h"
#include "renderer/passes/vsm_filter.h"
#include "renderer/render/antialiasing.h"
#include "renderer/render/frame_plan.h"
#include "renderer/scene/scene_fingerprint.h"
#include "renderer/scene/translucency.h"
#include "renderer/view/shadow_views.h"

namespace omnishadow {
namespace {

// From this many maps drawn in one context, their CPU work is done ahead on threads of its own
// (drawSpread): fewer gain less than the threads cost to start.
constexpr std::size_t kPlannedAheadLights = 16;
// Planning a light takes one thread about 35 us (256 lights on 1M triangles, llvmpipe's host);
// the H200 draws one in 140-290 us. Two threads keep well ahead; more only cost more to start:
// with 16, that frame's first shadow maps took 4 ms longer (docs/performance.md).
constexpr std::size_t kPlanningThreads = 2;

// Ends a stage's GL work: glFinish, with the time it blocked recorded as the stage's GPU wait.
void finishStage(StageTimes& times, const std::string& stage) {
  const auto start = std::chrono::steady_clock::now();
  glFinish();
  times.addWait(stage, millisecondsSince(start));
}

// Ends the upload's or the shadow maps' GL work (RenderSettings::finishEachStage): glFinish on a
// software rasterizer or when asked, else glFlush, so that the GPU starts on it while the next
// stage's CPU work is done.
void endStage(StageTimes& times, const std::string& stage, bool finish) {
  if (finish)
    finishStage(times, stage);
  else
    glFlush();
}

// GL_MESA_pack_invert's pixel store parameter (not in glcorearb.h).
constexpr GLenum kPackInvertMesa = 0x8758;

bool hasExtension(const char* name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i)
    if (std::string_view(reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, i))) == name)
      return true;
  return false;
}

// Reads attachment `index` as RGBA floats, top row first unless `glRowOrder`. `packInvert`:
// the driver has GL_MESA_pack_invert and turns the rows around while it copies them, which
// saves a second pass over the frame.
FloatPixels readAttachment(const FrameTargets& targets, int index, bool glRowOrder,
                           bool packInvert) {
  const int w = targets.width(), h = targets.height();
  FloatPixels pixels(static_cast<std::size_t>(w) * h * 4);  // GL writes every sample
  const bool invert = packInvert && !glRowOrder;
  if (invert) glPixelStorei(kPackInvertMesa, GL_TRUE);
  glGetTextureImage(targets.color(index), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(pixels.size() * sizeof(float)), pixels.data());
  if (invert) glPixelStorei(kPackInvertMesa, GL_FALSE);
  if (glRowOrder || invert) return pixels;
  const std::size_t row = static_cast<std::size_t>(w) * 4;
  for (int y = 0; y < h / 2; ++y)
    std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row,
                     pixels.begin() + (h - 1 - y) * row);
  return pixels;
}

// The RGB bytes of an Srgb8 target, first row = top.
Srgb8Image readSrgb8(const FrameTargets& targets, bool glRowOrder, gl::PixelPackBuffer* readback) {
  return readSrgb8Texture(targets.color(0), targets.width(), targets.height(), targets.drawn(),
                          glRowOrder, readback);
}

// Whether the lighting pass can encode the frame's beauty into 8-bit sRGB itself
// (RenderSettings::srgb8Exposure): a single sample, no AOVs, nothing to blend, which an
// integer target cannot, and nothing see-through, which reads the float beauty behind it.
bool encodesSrgb8(const Scene& scene, const RenderSettings& settings) {
  if (!settings.srgb8Exposure || settings.aovs || settings.antialiasing != 1) return false;
  return std::none_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) {
    return m.alphaMode == AlphaMode::Blend || hasTransmission(m);
  });
}

// Whether the frame draws the beauty pass: always without AOVs; with them only for a debug view
// or anti-aliasing, which the AOV pass does not draw.
bool drawsBeauty(const RenderSettings& settings) {
  return !settings.aovs || settings.debugView != DebugView::None || settings.antialiasing > 1;
}

bool hasBlendedSurfaces(const GpuScene& scene) {
  for (const GpuDraw& draw : scene.draws())
    if (scene.materials()[draw.material].desc.alphaMode == AlphaMode::Blend) return true;
  return false;
}

// The pixels of `aovs` that blended surfaces cover (A > 0) and no opaque one does (no camera
// distance): the AOV pass leaves them without P and N. Their channels from P.X on are replaced
// by those of `drawBlended()`, the AOVs of the front-most blended surfaces. Returns the mask,
// empty when no pixel is such.
template <typename DrawBlended>
std::vector<std::uint8_t> blendedOnlyPixels(const GpuScene& scene, FloatImage& aovs,
                                            DrawBlended drawBlended) {
  if (!hasBlendedSurfaces(scene)) return {};
  const std::size_t count = static_cast<std::size_t>(aovs.width) * aovs.height;
  const std::size_t stride = aovs.channels.size();
  constexpr int kA = 3, kPx = 4, kZ = 10;
  std::vector<std::uint8_t> mask(count, 0);
  bool any = false;
  for (std::size_t i = 0; i < count; ++i) {
    mask[i] = aovs.pixels[i * stride + kA] > 0.0f && aovs.pixels[i * stride + kZ] == 0.0f;
    any = any || mask[i];
  }
  if (!any) return {};
  const FloatImage blended = drawBlended();
  for (std::size_t i = 0; i < count; ++i) {
    mask[i] = mask[i] && blended.pixels[i * stride + kZ] > 0.0f;
    if (mask[i])
      std::copy(blended.pixels.begin() + i * stride + kPx,
                blended.pixels.begin() + (i + 1) * stride, aovs.pixels.begin() + i * stride + kPx);
  }
  return mask;
}

// An RG32F id target as read back: objectId and coverage per pixel, rows in GL order.
struct IdPixels {
  int width = 0, height = 0;
  bool glRowOrder = false;
  FloatPixels rg;
  // Row y, first = top (unless glRowOrder), as id, coverage pairs.
  const float* row(int y) const {
    const int glRow = glRowOrder ? y : height - 1 - y;
    return rg.data() + static_cast<std::size_t>(glRow) * width * 2;
  }
};

// Read as it is, RG floats: no conversion to RGBA, no band copies.
IdPixels readIdPixels(const FrameTargets& targets, int attachment, bool glRowOrder) {
  const int width = targets.width(), height = targets.height();
  IdPixels ids{width, height, glRowOrder,
               FloatPixels(static_cast<std::size_t>(width) * height * 2)};
  // In bands: a call's byte count is a GLsizei, and a 16384-pixel row of RG floats is 128 KiB.
  constexpr int kRows = 256;
  for (int y0 = 0; y0 < height; y0 += kRows) {
    const int rows = std::min(kRows, height - y0);
    glGetTextureSubImage(
        targets.color(attachment), 0, 0, y0, 0, width, rows, 1, GL_RG, GL_FLOAT,
        static_cast<GLsizei>(static_cast<std::size_t>(rows) * width * 2 * sizeof(float)),
        ids.rg.data() + static_cast<std::size_t>(y0) * width * 2);
  }
  return ids;
}

}  // namespace

class Renderer::Impl {
 public:
  explicit Impl(const ContextOptions& options);

  Frame render(const Scene& scene, const std::vector<Light>& lights, const Ambience& ambience,
               const ViewCamera& camera, const RenderSettings& settings, StageTimes& times);
  std::vector<CubeDistances> renderShadowDistances(const Scene& scene,
                                                   const std::vector<Light>& lights,
                                                   ShadowPassStrategy strategy, bool parallel);
  double prepare(const std::vector<Light>& lights, int width, int height,
                 const RenderSettings& settings, double budgetMiB, double minimumMiB);
  void prepareEnvironment(const EnvironmentLight& environment) {
    try {
      environmentCache_.bind(environment);
    } catch (const InputError&) {
      // render() reports it, after the scene's own errors.
    }
  }
  double frameBytes(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
                    const RenderSettings& settings) const;

  const RenderLimits& limits() const { return limits_; }
  const EglContext& context() const { return context_; }

 private:
  struct Prepared;
  LightingPass& lightingPass(Shading shading, PassOutputs outputs,
                             const LightingFeatures& features);
  FrameTargets& beautyTargets(int width, int height, PassOutputs outputs);
  // `fingerprint`: the scene's shadowFingerprint() where the shadow cache may be used.
  void renderShadows(Prepared& prepared, ShadowAtlasPlan plan, const Scene& scene,
                     const std::vector<Light>& lights, const RenderSettings& settings,
                     std::optional<std::uint64_t> fingerprint, Frame* frame);
  // The other strategies: `drawn` split between this context and the second one
  // (ShadowWorker), where it pays; `finishLight` after each map.
  template <class DrawOne, class Finish>
  void drawSpread(Prepared& prepared, const SceneCasters* casters, std::vector<ShadowJob>& drawn,
                  ShadowPassStrategy strategy, bool everyCaster, const RenderSettings& settings,
                  Frame* frame, const DrawOne& drawHere, const Finish& finishLight);
  // ShadowPassStrategy::Batched: `drawn`'s point lights without moments in batches
  // (ShadowPass::renderBatched), the others with `drawOne`.
  template <class DrawOne>
  void drawBatched(Prepared& prepared, const SceneCasters& casters, std::vector<ShadowJob>& drawn,
                   bool everyCaster, const DrawOne& drawOne);
  std::vector<ShadowMapDump> readShadowMaps(const Prepared& prepared, StageTimes& times);
  std::vector<PlanarShadowMapDump> readPlanarShadowMaps(const Prepared& prepared,
                                                        StageTimes& times);
  void drawImages(Prepared& prepared, const std::vector<Light>& lights, const ViewCamera& camera,
                  const LightingAmbience& ambient, const RenderSettings& settings, int debugLight,
                  Frame& frame, StageTimes& times);
  // The float beauty into `outputs`' targets (Beauty, or BeautyIds: the ids into `ids`).
  FloatImage drawBeauty(Prepared& prepared, const ViewCamera& camera,
                        const LightingAmbience& ambient, const RenderSettings& settings,
                        const PassParameters& parameters, StageTimes* times,
                        PassOutputs outputs = PassOutputs::Beauty, IdPixels* ids = nullptr);
  // The beauty's lighting pass into its targets of `outputs` (the "lighting" stage, to the GPU's
  // finish); the callers read them back.
  FrameTargets& drawLighting(Prepared& prepared, const ViewCamera& camera,
                             const LightingAmbience& ambient, const RenderSettings& settings,
                             const PassParameters& parameters, PassOutputs outputs,
                             StageTimes& times);
  // frame.srgb8, and frame.objectIds where the beauty's outputs are Srgb8Ids.
  void drawSrgb8(Prepared& prepared, const ViewCamera& camera, const LightingAmbience& ambient,
                 const RenderSettings& settings, PassParameters parameters, Frame& frame,
                 StageTimes& times);
  // Where a frame whose beauty the lighting pass draws in float has it encoded: Gpu, CpuInBands,
  // or Caller where the frame keeps the float beauty (RenderSettings::floatBeautyEncoding).
  FloatBeautyEncoding floatBeautyEncoder(const RenderSettings& settings) const;
  // The float beauty's pass, then its 8-bit encoding on the GPU (Srgb8Resolve) or on the CPU as
  // it is read back: for frames with srgb8Exposure the lighting pass cannot encode itself
  // (blended or see-through surfaces).
  void drawResolvedSrgb8(FloatBeautyEncoding encoder, Prepared& prepared, const ViewCamera& camera,
                         const LightingAmbience& ambient, const RenderSettings& settings,
                         const PassParameters& parameters, Frame& frame, StageTimes& times,
                         IdPixels& ids);
  // With one sample, the ids beside it into `ids` where the beauty's outputs are BeautyIds.
  FloatImage drawAntialiasedBeauty(Prepared& prepared, const ViewCamera& camera,
                                   const LightingAmbience& ambient, const RenderSettings& settings,
                                   const PassParameters& parameters, StageTimes& times,
                                   IdPixels& ids);
  void drawAovs(Prepared& prepared, const ViewCamera& camera, const LightingAmbience& ambient,
                const RenderSettings& settings, FloatImage& aovs, StageTimes& times);
  // The extra layers (albedo, ids, per-light diffuse and specular) after the fixed channels and
  // the visibility; `blendedOnly` marks the pixels that take the front-most blended surface.
  void drawAovLayers(Prepared& prepared, const ViewCamera& camera, const LightingAmbience& ambient,
                     const RenderSettings& settings, const std::vector<std::uint8_t>& blendedOnly,
                     FloatImage& aovs, StageTimes& times);
  // Frame::objectIds without the AOV pass (RenderSettings::objectIds). `drawn`: the ids the
  // beauty's draws wrote beside it (BeautyIds), which the pass then completes where a pixel
  // takes the front-most blended surface's id; empty: the pass draws them all.
  FloatImage drawObjectIds(Prepared& prepared, const ViewCamera& camera,
                           const LightingAmbience& ambient, const RenderSettings& settings,
                           StageTimes& times, IdPixels drawn = {});
  std::vector<LightView> drawLightViews(Prepared& prepared, const ViewCamera& camera,
                                        const LightingAmbience& ambient,
                                        const RenderSettings& settings);
  // The beauty's depth pre-pass (PassParameters::depthPrepass: the same picture either way).
  // DepthPrepass::On and Off are taken as they are. Auto chooses per scene (its shadow
  // fingerprint) and camera where the driver allows it, by `estimate` (the fragments through
  // the pre-pass and shaded after it, estimated on the CPU): where the pre-pass would let
  // through hardly more than are then shaded (few surfaces hide others), the frames shade
  // without it. A scene's first frame estimates; later frames keep that choice, estimating
  // again every kPrepassReestimate-th frame if the camera has moved since.
  void choosePrepass(std::uint64_t scene, DepthPrepass requested, const ViewCamera& camera,
                     const std::function<OverdrawCounts()>& estimate, PassParameters& parameters);
  // Whether `counts` say the pre-pass costs more than it spares.
  static bool prepassSparesTooLittle(const OverdrawCounts& counts);
  static constexpr int kPrepassReestimate = 8;
  // Percent more fragments through the pre-pass than shaded after it below which it is dropped.
  static constexpr int kPrepassMinOverdraw = 10;
  // Fragments the pre-pass must spare the shading per opaque triangle it draws, or it is dropped.
  static constexpr int kPrepassMinSparedPerTriangle = 2;
  struct PrepassChoice {
    std::uint64_t scene = 0;
    glm::mat4 viewProjection{0.0f};  // the camera the choice was estimated for
    int width = 0, height = 0;
    int frames = 0;  // frames since that estimate
    bool skip = false;
  };
  PrepassChoice prepassChoice_;

  EglContext context_;
  // Made by the first frame that can use it (shadowWorker()); before context_ in destruction.
  std::unique_ptr<ShadowWorker> shadowWorker_;
  bool shadowWorkerFailed_ = false;  // its context could not be made: not tried again
  // Whether this renderer has rendered a frame. The first one does without the worker: a single
  // render would pay for its context and shader variants (WhackAMole's first frame 4 ms longer,
  // its process 10) and have no later frame to repay them.
  bool renderedBefore_ = false;
  bool softwareRasterizer_ = false;  // llvmpipe: where the worker pays
  bool debug_ = false;               // ContextOptions::debug, for the worker's context
  ShadowWorker* shadowWorker(const RenderSettings& settings);
  std::unique_ptr<ShadowPass> shadowPass_;
  std::unique_ptr<VsmFilter> vsmFilter_;
  std::unique_ptr<TransmittancePass> transmittancePass_;  // made by the first translucent light
  std::unique_ptr<Srgb8Resolve> srgb8Resolve_;  // made by the first float frame with srgb8Exposure
  gl::PixelPackBuffer srgb8Readback_;           // the 8-bit beauty's, but on llvmpipe
  TextureCache textureCache_;    // the last render's scene textures, for a render of it again
  GeometryCache geometryCache_;  // the last render's scene geometry, likewise
  // The digests of the last render's meshes (hashed once for both caches, the geometry's and
  // the shadow maps'), of its images as far as the texture cache took them, and of the images
  // the shadow fingerprint hashed: the next render of the same nonzero Scene::revision takes
  // them instead of hashing the bytes again.
  struct SceneDigests {
    std::uint64_t revision = 0;
    std::vector<MeshDigests> meshes;
    ImageDigests images;
    ImageHashes casterImages;
  };
  SceneDigests sceneDigests_;
  SceneDigests& sceneDigests(const Scene& scene);
  TransmittanceAtlas transmittanceAtlas() const {
    return transmittancePass_ ? transmittancePass_->atlas() : TransmittanceAtlas{};
  }
  ShadowTexturePool shadowTextures_;
  // The last frame's shadow maps, kept for the next render of the same scene (batch jobs of
  // one scene with several cameras): point and spot maps do not depend on the camera.
  struct ShadowCache {
    std::uint64_t scene = 0;
    bool everyCaster = false;  // drawn for a read-back (ShadowPass::render)
    ShadowAtlasPlan plan;
    std::vector<Light> lights;
    ShadowGroups groups;
  };
  std::optional<ShadowCache> shadowCache_;
  RenderLimits limits_;
  std::string glRenderer_;
  bool prepassSupported_ = true;  // depthPrepassSupported(glRenderer_)
  bool packInvert_ = false;       // GL_MESA_pack_invert: readbacks turn the rows around themselves
  bool ballot_ = false;           // GL_ARB_shader_ballot: LightingFeatures::facingLightLoop
  struct PassKey {
    Shading shading;
    PassOutputs outputs;
    LightingFeatures features;
  };
  std::vector<std::pair<PassKey, std::unique_ptr<LightingPass>>> lightingPasses_;
  // The beauty pass's targets, kept for the next frame of the same size: a fresh 1280x720
  // RGBA32F target costs its pages again (allocation, faults, zeroing) on every frame. The pass
  // clears them itself. One slot for the float beauty, one for the 8-bit one: a scene with
  // blended surfaces takes the float one where the next may take the 8-bit one.
  std::array<std::unique_ptr<FrameTargets>, 2> beautyTargets_;
  // The AOV pass's targets (up to eight RGBA32F, 118 MB at 1280x720), kept while frames ask for
  // AOVs: a frame's AOV memory (checkAovMemory) is the same whether they are new or kept, and a
  // frame without AOVs lets them go.
  std::unique_ptr<FrameTargets> aovTargets_;
  std::unique_ptr<FrameTargets> layerTargets_;  // the same for the AOV layer pass
  std::unique_ptr<FrameTargets> idTargets_;     // and for the ids of masks without AOVs
  EnvironmentCache environmentCache_;
};

// The scene on the GPU with its shadow maps, shared by every view of one render.
struct Renderer::Impl::Prepared {
  Prepared(const Scene& s, TextureCache* textures, GeometryCache* geometry,
           const std::vector<MeshDigests>* meshes, ImageDigests* images)
      : scene(s), gpu(s, textures, geometry, meshes, images) {}
  const Scene& scene;
  GpuScene gpu;
  LightingFeatures features;
  PassOutputs beautyOutputs = PassOutputs::Beauty;  // beautyOutputs()
  std::uint64_t fingerprint = 0;  // shadowFingerprint() when the shadow cache is used
  bool everyCaster = false;       // the maps hold every caster (readsShadowMaps)
  ShadowAtlasPlan atlas;
  ShadowGroups groups;  // indexed like atlas.groups
  std::vector<ShadedLight> shaded;
  std::vector<bool> translucent;  // per light: translucentShadowLights()
};

namespace {

// The texels of the largest square RGBA32F target (the frame's color format) the GL accepts,
// by bisection with proxy textures, which allocate nothing.
long long largestFrameTexels(int maxSide) {
  const auto fits = [](int side) {
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GL_RGBA32F, side, side, 0, GL_RGBA, GL_FLOAT, nullptr);
    GLint width = 0;
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
    return width == side;
  };
  int low = 1, high = std::max(maxSide, 1);
  while (low < high) {
    const int middle = low + (high - low + 1) / 2;
    if (fits(middle)) {
      low = middle;
    } else {
      high = middle - 1;
    }
  }
  return static_cast<long long>(low) * low;
}

// Frame::objectIds come from a pass of their own: asked for without AOVs (with them, from
// the AOVs' objectId layer).
bool drawsObjectIdPass(const RenderSettings& settings) {
  return settings.objectIds && !settings.aovs;
}

// The beauty pass's targets: the 8-bit one where the lighting pass may encode the PNG's bytes,
// else the float one; with the ids of masks beside them, written by the beauty's draws (not
// with anti-aliasing: its samples are off the pixel centers, where the ids are taken).
PassOutputs floatBeautyOutputs(const RenderSettings& settings) {
  const bool ids = drawsObjectIdPass(settings) && settings.antialiasing == 1;
  return ids ? PassOutputs::BeautyIds : PassOutputs::Beauty;
}

PassOutputs beautyOutputs(const Scene& scene, const RenderSettings& settings) {
  if (!encodesSrgb8(scene, settings)) return floatBeautyOutputs(settings);
  return drawsObjectIdPass(settings) ? PassOutputs::Srgb8Ids : PassOutputs::Srgb8;
}

// The AOV pass holds all its targets at once (with the layer pass's, when layers are asked
// for) and fills the AOV image: together far more than the one RGBA32F target the frame-size
// check covers. The id pass of masks without AOVs holds its target and four channels of ids
// and coverage. Their sum is checked before anything is allocated.
void checkAovMemory(const std::vector<Light>& lights, const ViewCamera& camera,
                    const RenderSettings& settings) {
  if (!settings.aovs && !drawsObjectIdPass(settings)) return;
  const int width = camera.width, height = camera.height;
  double targets = 0.0;
  std::size_t channels = 4;  // drawObjectIds(): ids and coverage, blended ids, the result
  if (settings.aovs) {
    targets = FrameTargets::bytes(width, height, PassOutputs::Aovs);
    if (settings.layers.any()) targets += FrameTargets::bytes(width, height, PassOutputs::Layers);
    channels = aovChannels(lights, settings.layers).size();
  } else {
    targets = FrameTargets::bytes(width, height, PassOutputs::Ids);
  }
  const double image =
      static_cast<double>(width) * height * static_cast<double>(channels) * sizeof(float);
  constexpr double kMiB = 1024.0 * 1024.0;
  if ((targets + image) / kMiB <= settings.maxAovMemoryMiB) return;
  char message[320];
  std::snprintf(message, sizeof message,
                "the %s pass at %dx%d needs %.0f MiB (render targets %.0f MiB, %s image %.0f "
                "MiB), more than the %.0f MiB allowed (--max-memory): lower --width/--height or "
                "raise --max-memory",
                settings.aovs ? "AOV" : "mask", width, height, (targets + image) / kMiB,
                targets / kMiB, settings.aovs ? "AOV" : "id", image / kMiB,
                settings.maxAovMemoryMiB);
  throw InputError(message);
}

}  // namespace

Renderer::Impl::Impl(const ContextOptions& options) : context_(options) {
  if (options.debug) gl::enableDebugOutput();
  gl::applyContextDefaults();
  shadowPass_ = std::make_unique<ShadowPass>();
  vsmFilter_ = std::make_unique<VsmFilter>();
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &limits_.maxArrayLayers);
  glGetIntegerv(GL_MAX_CUBE_MAP_TEXTURE_SIZE, &limits_.maxCubeMapSize);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &limits_.maxTextureSize);
  limits_.maxFrameTexels = largestFrameTexels(limits_.maxTextureSize);
  glRenderer_ = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  prepassSupported_ = depthPrepassSupported(glRenderer_);
  softwareRasterizer_ = gl::isLlvmpipe(glRenderer_);
  shadowTextures_ = ShadowTexturePool(softwareRasterizer_);
  debug_ = options.debug;
  packInvert_ = hasExtension("GL_MESA_pack_invert");
  ballot_ = hasExtension("GL_ARB_shader_ballot");
  gl::checkErrors("context setup");
}

namespace {

// Frames whose shadow maps are read back (depth dumps, the depth view) draw every caster into
// them: the maps are then the scene as the light sees it, floors and walls included.
bool readsShadowMaps(const RenderSettings& settings) {
  return settings.readShadowMaps || settings.debugView == DebugView::Depth;
}

bool sameGroups(const std::vector<ShadowGroupPlan>& a, const std::vector<ShadowGroupPlan>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!(a[i].key == b[i].key) || a[i].layers != b[i].layers) return false;
  return true;
}

// Whether a light's map, rendered before with `before` and `plan`, is what `light` and `now`
// would render again. Directional maps follow the camera and are always rendered.
bool sameShadowMap(const Light& before, const LightShadowPlan& planBefore, const Light& light,
                   const LightShadowPlan& now) {
  if (light.type == LightType::Directional || before.type != light.type) return false;
  const ShadowSettings& a = before.shadow;
  const ShadowSettings& b = light.shadow;
  return planBefore.group == now.group && planBefore.firstLayer == now.firstLayer &&
         planBefore.layerCount == now.layerCount && planBefore.near == now.near &&
         planBefore.far == now.far && planBefore.viewProjection == now.viewProjection &&
         before.position == light.position && a.cullFace == b.cullFace &&
         a.polygonOffsetFactor == b.polygonOffsetFactor &&
         a.polygonOffsetUnits == b.polygonOffsetUnits && a.filter == b.filter &&
         a.filterRadius == b.filterRadius && a.translucent == b.translucent;
}

}  // namespace

void Renderer::Impl::renderShadows(Prepared& prepared, ShadowAtlasPlan atlas, const Scene& scene,
                                   const std::vector<Light>& lights, const RenderSettings& settings,
                                   std::optional<std::uint64_t> fingerprint, Frame* frame) {
  prepared.atlas = std::move(atlas);
  const bool useCache = fingerprint.has_value();
  prepared.fingerprint = fingerprint.value_or(0);
  std::optional<ShadowCache> cache = std::move(shadowCache_);
  shadowCache_.reset();
  // Maps that are read back hold every caster; the others leave out flat casters that shadow
  // nothing. Each kind is reused only for its own, so a picture never depends on the renders
  // before it.
  const bool everyCaster = readsShadowMaps(settings);
  prepared.everyCaster = everyCaster;
  const bool reuse = useCache && cache && cache->scene == *fingerprint &&
                     cache->everyCaster == everyCaster &&
                     sameGroups(cache->plan.groups, prepared.atlas.groups);
  if (reuse) {
    prepared.groups = std::move(cache->groups);
  } else {
    if (cache)
      for (ShadowGroupTextures& group : cache->groups) shadowTextures_.give(std::move(group));
    for (const ShadowGroupPlan& group : prepared.atlas.groups)
      prepared.groups.push_back(shadowTextures_.take(group));
  }
  auto cachedPlan = [&](std::size_t light) -> const LightShadowPlan* {
    if (!reuse || light >= cache->lights.size()) return nullptr;
    for (const LightShadowPlan& plan : cache->plan.lights)
      if (plan.light == static_cast<int>(light)) return &plan;
    return nullptr;
  };
  const ShadowPassStrategy strategy = resolveShadowPassStrategy(settings.shadowPass, glRenderer_);
  prepared.translucent = translucentShadowLights(lights, scene);
  // Where each translucent light's casters reach, and its place in the transmittance atlas.
  std::vector<TranslucentReach> reach(lights.size());
  for (const LightShadowPlan& plan : prepared.atlas.lights) {
    const auto i = static_cast<std::size_t>(plan.light);
    if (!prepared.translucent[i]) continue;
    const int resolution = prepared.groups[static_cast<std::size_t>(plan.group)].key.resolution;
    reach[i] = translucentReach(prepared.gpu, plan, resolution);
  }
  std::vector<AtlasLayers> places(lights.size());
  std::vector<bool> moved(lights.size(), false);
  if (std::find(prepared.translucent.begin(), prepared.translucent.end(), true) !=
      prepared.translucent.end()) {
    if (!transmittancePass_) transmittancePass_ = std::make_unique<TransmittancePass>();
    places = transmittancePass_->place(reach, moved);
  }
  // Described once a light needs its map drawn: frames whose maps are all reused (batch jobs
  // of one scene from several cameras) or that have none need no description.
  std::optional<SceneCasters> casters;
  std::vector<ShadowJob> drawn;                // the maps this frame draws, in light order
  std::vector<std::size_t> transmittanceOnly;  // reused maps whose transmittance layers moved
  std::size_t next = 0;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    ShadedLight s{&lights[i], nullptr};
    if (next < prepared.atlas.lights.size() &&
        prepared.atlas.lights[next].light == static_cast<int>(i)) {
      const LightShadowPlan& plan = prepared.atlas.lights[next++];
      const LightShadowPlan* before = cachedPlan(i);
      s.translucent = prepared.translucent[i];
      s.transmittanceFirst = places[i].first;
      s.transmittanceLayers = places[i].layers;
      if (before && sameShadowMap(cache->lights[i], *before, lights[i], plan)) {
        if (frame) ++frame->shadowMapsReused;
        // A reused map's transmittance is still in the atlas unless its layers moved there.
        if (s.translucent && moved[i]) transmittanceOnly.push_back(i);
      } else {
        drawn.push_back({&lights[i], &plan, &prepared.groups[plan.group]});
      }
      s.shadow = &plan;
    }
    prepared.shaded.push_back(s);
  }
  if (!drawn.empty()) casters = describeCasters(prepared.gpu);

  // What follows a light's map: its VSM blur, then its transmittance (tested against the map).
  auto finishLight = [&](const ShadowJob& job) {
    const auto i = static_cast<std::size_t>(job.light - lights.data());
    const ShadowGroupTextures& group = *job.target;
    if (group.key.moments) vsmFilter_->blur(*job.target, *job.plan, job.light->shadow.filterRadius);
    if (frame) {
      ++frame->shadowMapsRendered;
      frame->flatCastersLeftOut += job.flatCastersLeftOut;
    }
    if (prepared.translucent[i])
      transmittancePass_->render(prepared.gpu, lights[i], *job.plan, group, reach[i], places[i]);
  };
  auto drawHere = [&](ShadowJob& job) {
    job.flatCastersLeftOut =
        shadowPass_->render(prepared.gpu, prepared.gpu.vertexArrays(), *casters, *job.light,
                            *job.plan, *job.target, strategy, everyCaster, job.planned);
  };

  if (strategy == ShadowPassStrategy::Batched) {
    // No second context: it would split the batches, which are the point of this strategy.
    renderedBefore_ = true;
    if (!drawn.empty()) drawBatched(prepared, *casters, drawn, everyCaster, drawHere);
    for (const ShadowJob& job : drawn) finishLight(job);
  } else {
    drawSpread(prepared, casters ? &*casters : nullptr, drawn, strategy, everyCaster, settings,
               frame, drawHere, finishLight);
  }
  for (std::size_t i : transmittanceOnly) {
    const LightShadowPlan& plan = *prepared.shaded[i].shadow;
    transmittancePass_->render(prepared.gpu, lights[i], plan, prepared.groups[plan.group], reach[i],
                               places[i]);
  }
}

// Every other map to the worker, from the second on; the renderer draws the rest meanwhile.
template <class DrawOne, class Finish>
void Renderer::Impl::drawSpread(Prepared& prepared, const SceneCasters* casters,
                                std::vector<ShadowJob>& drawn, ShadowPassStrategy strategy,
                                bool everyCaster, const RenderSettings& settings, Frame* frame,
                                const DrawOne& drawHere, const Finish& finishLight) {
  std::vector<ShadowJob> workerJobs;
  ShadowWorker* worker = drawn.size() >= 2 && renderedBefore_ ? shadowWorker(settings) : nullptr;
  renderedBefore_ = true;
  if (worker) {
    for (std::size_t k = 1; k < drawn.size(); k += 2) workerJobs.push_back(drawn[k]);
    try {
      worker->start(prepared.gpu, *casters, workerJobs, strategy, everyCaster);
    } catch (const std::exception& e) {
      // One context draws them all, as on a GPU; said once, since it is not tried again.
      shadowWorkerFailed_ = true;
      worker = nullptr;
      workerJobs.clear();
      if (frame)
        frame->warnings.push_back(std::string("shadow maps are drawn in one GL context: ") +
                                  e.what());
    }
  }
  // One context drawing many maps (a GPU's): the lights' culling, draw lists and texel
  // rectangles worked out on other threads in light order while this one feeds the driver the
  // lights already planned. Not between each light's GL calls, where the driver waits for them
  // (256 lights on 1M triangles: 10 ms of CPU a frame on llvmpipe's host), nor all before the
  // first GL call, where the GPU waits: on the H200 that made the shadow maps 4-5 ms slower
  // (docs/performance.md).
  std::vector<ShadowPass::LightDraws> planned;
  std::optional<InOrderAhead> planning;
  if (!worker && casters && drawn.size() >= kPlannedAheadLights) {
    planned.resize(drawn.size());
    planning.emplace(drawn.size(), kPlanningThreads, [&](std::size_t first, std::size_t end) {
      for (std::size_t k = first; k < end; ++k)
        planned[k] = ShadowPass::planDraws(prepared.gpu, *casters, *drawn[k].light, *drawn[k].plan,
                                           *drawn[k].target, strategy, everyCaster);
    });
    for (std::size_t k = 0; k < drawn.size(); ++k) drawn[k].planned = &planned[k];
  }
  // Waits for the worker also when drawing here throws: it reads what this frame owns.
  struct WorkerWait {
    ShadowWorker* worker;
    ~WorkerWait() {
      if (!worker) return;
      try {
        worker->finish();
      } catch (...) {  // the error that unwinds this frame is the one reported
      }
    }
  } wait{worker};
  for (std::size_t k = 0; k < drawn.size(); ++k) {
    if (worker && k % 2 == 1) continue;
    if (planning) planning->ready(k);
    drawHere(drawn[k]);
    finishLight(drawn[k]);
  }
  if (worker) {
    wait.worker = nullptr;
    worker->finish();
    for (const ShadowJob& job : workerJobs) finishLight(job);
    if (frame) frame->shadowMapsInParallel += static_cast<int>(workerJobs.size());
  }
}

template <class DrawOne>
void Renderer::Impl::drawBatched(Prepared& prepared, const SceneCasters& casters,
                                 std::vector<ShadowJob>& drawn, bool everyCaster,
                                 const DrawOne& drawOne) {
  // Point lights without moments go in batches of one texture and one raster setting; the
  // others are drawn one by one, as Six draws them.
  struct Batch {
    ShadowGroupTextures* target;
    const ShadowSettings* settings;
    std::vector<std::size_t> jobs;
  };
  std::vector<Batch> batches;
  for (std::size_t k = 0; k < drawn.size(); ++k) {
    ShadowJob& job = drawn[k];
    if (job.target->key.layout != ShadowLayout::Cube || job.target->key.moments) {
      drawOne(job);
      continue;
    }
    const ShadowSettings& s = job.light->shadow;
    const auto same = [&](const Batch& b) {
      return b.target == job.target && b.settings->cullFace == s.cullFace &&
             b.settings->polygonOffsetFactor == s.polygonOffsetFactor &&
             b.settings->polygonOffsetUnits == s.polygonOffsetUnits;
    };
    const auto found = std::find_if(batches.begin(), batches.end(), same);
    if (found != batches.end())
      found->jobs.push_back(k);
    else
      batches.push_back({job.target, &s, {k}});
  }
  for (const Batch& batch : batches) {
    std::vector<ShadowPass::BatchedLight> lights;
    for (const std::size_t k : batch.jobs) lights.push_back({drawn[k].light, drawn[k].plan});
    // Whether the texture holds no other light's map this frame (a reused one, or another
    // batch's).
    std::size_t planned = 0;
    for (const LightShadowPlan& plan : prepared.atlas.lights)
      planned += &prepared.groups[static_cast<std::size_t>(plan.group)] == batch.target;
    const std::vector<int> flat =
        shadowPass_->renderBatched(prepared.gpu, prepared.gpu.vertexArrays(), casters, lights,
                                   *batch.target, everyCaster, planned == batch.jobs.size());
    for (std::size_t i = 0; i < batch.jobs.size(); ++i)
      drawn[batch.jobs[i]].flatCastersLeftOut = flat[i];
  }
}

ShadowWorker* Renderer::Impl::shadowWorker(const RenderSettings& settings) {
  if (!settings.parallelShadowMaps || !softwareRasterizer_ || shadowWorkerFailed_) return nullptr;
  if (!shadowWorker_) shadowWorker_ = std::make_unique<ShadowWorker>(context_, debug_);
  return shadowWorker_.get();
}

LightingPass& Renderer::Impl::lightingPass(Shading shading, PassOutputs outputs,
                                           const LightingFeatures& features) {
  for (auto& [key, pass] : lightingPasses_)
    if (key.shading == shading && key.outputs == outputs && key.features == features) return *pass;
  lightingPasses_.emplace_back(PassKey{shading, outputs, features},
                               std::make_unique<LightingPass>(shading, outputs, features));
  return *lightingPasses_.back().second;
}

namespace {

// An R32F id target (PassOutputs::Srgb8Ids) as Frame::objectIds holds it, read in bands.
FloatImage readObjectIds(const FrameTargets& targets, int attachment, bool glRowOrder) {
  const int width = targets.width(), height = targets.height();
  FloatImage image{width, height, {"objectId"}, {}};
  image.pixels.resize(static_cast<std::size_t>(width) * height);
  constexpr int kRows = 256;  // a call's byte count is a GLsizei
  FloatPixels band(static_cast<std::size_t>(width) * std::min(kRows, height));
  for (int y0 = 0; y0 < height; y0 += kRows) {
    const int rows = std::min(kRows, height - y0);
    glGetTextureSubImage(
        targets.color(attachment), 0, 0, y0, 0, width, rows, 1, GL_RED, GL_FLOAT,
        static_cast<GLsizei>(static_cast<std::size_t>(rows) * width * sizeof(float)), band.data());
    for (int r = 0; r < rows; ++r) {
      const int y = glRowOrder ? y0 + r : height - 1 - (y0 + r);
      std::copy_n(band.data() + static_cast<std::size_t>(r) * width, width,
                  image.pixels.data() + static_cast<std::size_t>(y) * width);
    }
  }
  return image;
}

// The ids as Frame::objectIds holds them; `anyBlendedOnly` tells whether some pixel is covered
// by blended surfaces alone (no opaque id, coverage above 0).
FloatImage objectIdsOf(const IdPixels& ids, bool& anyBlendedOnly) {
  FloatImage image{ids.width, ids.height, {"objectId"}, {}};
  image.pixels.resize(static_cast<std::size_t>(ids.width) * ids.height);
  bool any = false;
  for (int y = 0; y < ids.height; ++y) {
    const float* from = ids.row(y);
    float* to = image.pixels.data() + static_cast<std::size_t>(y) * ids.width;
    for (int x = 0; x < ids.width; ++x) {
      to[x] = from[2 * x];
      any |= from[2 * x] < 0.0f && from[2 * x + 1] > 0.0f;
    }
  }
  anyBlendedOnly = any;
  return image;
}

// `kept`, remade first when it is missing or of another size, attachments or shape (one slot
// holds the beauty's targets with and without the ids).
// `llvmpipe`: the driver fills new textures with zero bytes and keeps them in this process's
// memory (FrameTargets' madeZeroed and zerosByUpload).
FrameTargets& keptTargets(std::unique_ptr<FrameTargets>& kept, bool llvmpipe, int width, int height,
                          PassOutputs outputs,
                          int visibilityOutputs = contract::kMaxVisibilityOutputs) {
  if (!kept || kept->width() != width || kept->height() != height || kept->outputs() != outputs ||
      (outputs == PassOutputs::Aovs && kept->visibilityOutputs() != visibilityOutputs)) {
    kept.reset();  // the old one goes before the new one takes its memory
    kept = std::make_unique<FrameTargets>(width, height, outputs, visibilityOutputs, llvmpipe,
                                          llvmpipe);
  }
  return *kept;
}

}  // namespace

FrameTargets& Renderer::Impl::beautyTargets(int width, int height, PassOutputs outputs) {
  return keptTargets(beautyTargets_[writesSrgb8(outputs) ? 1 : 0], softwareRasterizer_, width,
                     height, outputs);
}

FrameTargets& Renderer::Impl::drawLighting(Prepared& prepared, const ViewCamera& camera,
                                           const LightingAmbience& ambient,
                                           const RenderSettings& settings,
                                           const PassParameters& parameters, PassOutputs outputs,
                                           StageTimes& times) {
  FrameTargets& targets = beautyTargets(camera.width, camera.height, outputs);
  ScopedStage stage(times, "lighting");
  lightingPass(settings.shading, outputs, prepared.features)
      .render(prepared.gpu, camera, prepared.shaded, prepared.groups, transmittanceAtlas(), ambient,
              targets, parameters);
  finishStage(times, "lighting");
  return targets;
}

FloatImage Renderer::Impl::drawBeauty(Prepared& prepared, const ViewCamera& camera,
                                      const LightingAmbience& ambient,
                                      const RenderSettings& settings,
                                      const PassParameters& parameters, StageTimes* times,
                                      PassOutputs outputs, IdPixels* ids) {
  StageTimes unused;
  StageTimes& stages = times ? *times : unused;
  FrameTargets& targets =
      drawLighting(prepared, camera, ambient, settings, parameters, outputs, stages);
  ScopedStage readback(stages, "readback");
  FloatImage image{camera.width, camera.height, {"R", "G", "B", "A"}, {}};
  image.pixels = readAttachment(targets, 0, camera.glRowOrder, packInvert_);
  if (outputs == PassOutputs::BeautyIds && ids) *ids = readIdPixels(targets, 1, camera.glRowOrder);
  return image;
}

void Renderer::Impl::drawSrgb8(Prepared& prepared, const ViewCamera& camera,
                               const LightingAmbience& ambient, const RenderSettings& settings,
                               PassParameters parameters, Frame& frame, StageTimes& times) {
  const PassOutputs outputs = prepared.beautyOutputs;
  parameters.exposureScale = std::exp2(*settings.srgb8Exposure);  // as toSrgb8() scales
  FrameTargets& targets =
      drawLighting(prepared, camera, ambient, settings, parameters, outputs, times);
  ScopedStage readback(times, "readback");
  frame.srgb8 =
      readSrgb8(targets, camera.glRowOrder, softwareRasterizer_ ? nullptr : &srgb8Readback_);
  // Without blended surfaces no pixel takes a blended surface's id: the ids are complete.
  if (outputs == PassOutputs::Srgb8Ids)
    frame.objectIds = readObjectIds(targets, 1, camera.glRowOrder);
}

FloatBeautyEncoding Renderer::Impl::floatBeautyEncoder(const RenderSettings& settings) const {
  if (!settings.srgb8Exposure || settings.aovs || settings.antialiasing != 1)
    return FloatBeautyEncoding::Caller;
  if (settings.floatBeautyEncoding != FloatBeautyEncoding::Auto)
    return settings.floatBeautyEncoding;
  return softwareRasterizer_ ? FloatBeautyEncoding::CpuInBands : FloatBeautyEncoding::Gpu;
}

void Renderer::Impl::drawResolvedSrgb8(FloatBeautyEncoding encoder, Prepared& prepared,
                                       const ViewCamera& camera, const LightingAmbience& ambient,
                                       const RenderSettings& settings,
                                       const PassParameters& parameters, Frame& frame,
                                       StageTimes& times, IdPixels& ids) {
  const PassOutputs outputs = prepared.beautyOutputs;
  FrameTargets& targets =
      drawLighting(prepared, camera, ambient, settings, parameters, outputs, times);
  ScopedStage readback(times, "readback");
  const float exposureScale = std::exp2(*settings.srgb8Exposure);  // as toSrgb8() scales
  if (encoder == FloatBeautyEncoding::CpuInBands) {
    frame.srgb8 = readSrgb8InBands(targets.color(0), camera.width, camera.height, targets.drawn(),
                                   exposureScale, camera.glRowOrder);
  } else {
    if (!srgb8Resolve_) srgb8Resolve_ = std::make_unique<Srgb8Resolve>();
    frame.srgb8 = srgb8Resolve_->resolve(targets.color(0), camera.width, camera.height,
                                         exposureScale, camera.glRowOrder);
  }
  if (outputs == PassOutputs::BeautyIds) ids = readIdPixels(targets, 1, camera.glRowOrder);
}

// The mean of the beauty through each sample offset (one offset, the pixel center, without
// anti-aliasing); the shadow maps are shared by every sample.
FloatImage Renderer::Impl::drawAntialiasedBeauty(Prepared& prepared, const ViewCamera& camera,
                                                 const LightingAmbience& ambient,
                                                 const RenderSettings& settings,
                                                 const PassParameters& parameters,
                                                 StageTimes& times, IdPixels& ids) {
  if (settings.antialiasing == 1)
    return drawBeauty(prepared, camera, ambient, settings, parameters, &times,
                      prepared.beautyOutputs, &ids);
  const std::vector<glm::vec2> offsets = antialiasingOffsets(settings.antialiasing);
  FloatImage sum;
  for (const glm::vec2& offset : offsets) {
    const FloatImage sample =
        drawBeauty(prepared, jitteredCamera(camera, offset), ambient, settings, parameters, &times);
    if (sum.pixels.empty()) {
      sum = sample;
      continue;
    }
    for (std::size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += sample.pixels[i];
  }
  const float scale = 1.0f / static_cast<float>(offsets.size());
  for (float& value : sum.pixels) value *= scale;
  return sum;
}

void Renderer::Impl::drawAovs(Prepared& prepared, const ViewCamera& camera,
                              const LightingAmbience& ambient, const RenderSettings& settings,
                              FloatImage& aovs, StageTimes& times) {
  const int lightCount = static_cast<int>(prepared.shaded.size());
  const bool flip = camera.glRowOrder;
  // Where each light's transmittance.<light>.R channel is (-1: none).
  std::vector<int> transmittanceChannel(prepared.shaded.size(), -1);
  bool hasTransmittance = false;
  for (std::size_t l = 0; l < prepared.shaded.size(); ++l) {
    if (!prepared.shaded[l].translucent) continue;
    transmittanceChannel[l] =
        aovs.channelIndex("transmittance." + prepared.shaded[l].light->name + ".R");
    hasTransmittance = hasTransmittance || transmittanceChannel[l] >= 0;
  }
  // The first pass gives the fixed channels; the lights' shadow terms take the passes and
  // visibility targets aovVisibilityLayout() gives.
  const AovVisibilityLayout layout = aovVisibilityLayout(lightCount, hasTransmittance);
  LightingFeatures features = prepared.features;
  features.visibilityOutputs = layout.outputs;
  FrameTargets& targets = keptTargets(aovTargets_, softwareRasterizer_, camera.width, camera.height,
                                      PassOutputs::Aovs, layout.outputs);
  LightingPass& pass = lightingPass(settings.shading, PassOutputs::Aovs, features);
  // One lighting pass into `targets`; the caller reads them back. Every pass after the first
  // draws the same frame, so it reads the first one's ambient occlusion estimate.
  bool drawnBefore = false;
  auto draw = [&](int visibilityBase, bool blendedOnly, int scalarTerms, int rgbFirst) {
    PassParameters parameters;
    parameters.reuseOcclusion = std::exchange(drawnBefore, true);
    parameters.visibilityBase = visibilityBase;
    parameters.blendedOnly = blendedOnly;
    parameters.scalarTerms = scalarTerms;
    parameters.rgbFirst = rgbFirst;
    ScopedStage stage(times, "lighting");
    pass.render(prepared.gpu, camera, prepared.shaded, prepared.groups, transmittanceAtlas(),
                ambient, targets, parameters);
    finishStage(times, "lighting");
  };
  // The copies of the scalar terms of lights [base, end) from channel 0 on.
  auto scalarCopies = [&](int base, int end, std::vector<ChannelCopy>& copies) {
    for (int first = base; first < end; first += 4)
      copies.push_back(
          {3 + (first - base) / 4, 0, std::min(4, end - first), kFixedAovChannels + first});
  };
  // The copies of the RGB terms of lights [base, end) from channel `rgbFirst` on; false when
  // none of them has transmittance channels.
  auto rgbCopies = [&](int base, int end, int rgbFirst, std::vector<ChannelCopy>& copies) {
    bool any = false;
    for (int l = base; l < end; ++l) {
      if (transmittanceChannel[l] < 0) continue;
      any = true;
      for (int c = 0; c < 3; ++c) {
        const int channel = rgbFirst + 3 * (l - base) + c;
        copies.push_back({3 + channel / 4, channel % 4, 1, transmittanceChannel[l] + c});
      }
    }
    return any;
  };
  // RGBA; P from the position target's RGB, N; Z from its A; the occlusion layer from the
  // normal target's A.
  std::vector<ChannelCopy> fixedCopies = {{0, 0, 4, 0}, {1, 0, 3, 4}, {2, 0, 3, 7}, {1, 3, 1, 10}};
  if (const int occlusion = aovs.channelIndex("occlusion"); occlusion >= 0)
    fixedCopies.push_back({2, 3, 1, occlusion});
  auto fill = [&](FloatImage& image, bool blendedOnly) {
    if (layout.combined) {
      draw(0, blendedOnly, lightCount, layout.scalarPerPass);
      ScopedStage readback(times, "readback");
      std::vector<ChannelCopy> copies = fixedCopies;
      scalarCopies(0, lightCount, copies);
      rgbCopies(0, lightCount, layout.scalarPerPass, copies);
      readChannels(targets, copies, flip, image);
      return;
    }
    for (int base = 0; base == 0 || base < lightCount; base += layout.scalarPerPass) {
      draw(base, blendedOnly, layout.scalarPerPass, -1);
      ScopedStage readback(times, "readback");
      std::vector<ChannelCopy> copies;
      if (base == 0) copies = fixedCopies;
      scalarCopies(base, std::min(base + layout.scalarPerPass, lightCount), copies);
      readChannels(targets, copies, flip, image);
    }
    if (!hasTransmittance) return;
    for (int base = 0; base < lightCount; base += layout.rgbPerPass) {
      std::vector<ChannelCopy> copies;
      if (!rgbCopies(base, std::min(base + layout.rgbPerPass, lightCount), 0, copies)) continue;
      draw(base, blendedOnly, 0, 0);
      ScopedStage readback(times, "readback");
      readChannels(targets, copies, flip, image);
    }
  };
  fill(aovs, false);
  // Pixels only blended surfaces cover (A > 0, no opaque distance) take P, N, Z, visibility and
  // the layers of the front-most blended surface (README, "Outputs").
  const std::vector<std::uint8_t> blendedOnly = blendedOnlyPixels(prepared.gpu, aovs, [&] {
    FloatImage blended = aovs;
    fill(blended, true);
    return blended;
  });
  drawAovLayers(prepared, camera, ambient, settings, blendedOnly, aovs, times);
}

FloatImage Renderer::Impl::drawObjectIds(Prepared& prepared, const ViewCamera& camera,
                                         const LightingAmbience& ambient,
                                         const RenderSettings& settings, StageTimes& times,
                                         IdPixels drawn) {
  // The id pass draws what the AOV pass draws, with its depth tests: where an opaque or masked
  // surface covers a pixel, its id is the AOVs' objectId. Its coverage finds the pixels that
  // take the front-most blended surface's id as the AOVs find them: covered (A > 0 there) by no
  // opaque surface (id -1; no camera distance in the AOVs).
  std::optional<ScopedStage> stage;  // where the pass draws
  PassParameters parameters;
  // Its shading is no dearer than the pre-pass's depth: the pre-pass would only draw the
  // triangles twice. Either way the nearest surface is drawn, the last of equally near ones.
  parameters.depthPrepass = false;
  IdPixels ids = std::move(drawn);
  auto draw = [&] {
    if (!stage) stage.emplace(times, "layers");
    FrameTargets& targets =
        keptTargets(idTargets_, softwareRasterizer_, camera.width, camera.height, PassOutputs::Ids);
    lightingPass(settings.shading, PassOutputs::Ids, prepared.features)
        .render(prepared.gpu, camera, prepared.shaded, prepared.groups, transmittanceAtlas(),
                ambient, targets, parameters);
    ids = readIdPixels(targets, 0, camera.glRowOrder);
  };
  if (ids.rg.empty()) draw();
  bool anyBlendedOnly = false;
  FloatImage objectIds = objectIdsOf(ids, anyBlendedOnly);
  if (!anyBlendedOnly) return objectIds;
  const IdPixels opaque = ids;
  parameters.blendedOnly = true;
  draw();  // the front-most blended surface's id
  for (int y = 0; y < ids.height; ++y) {
    const float* before = opaque.row(y);
    const float* blended = ids.row(y);
    float* to = objectIds.pixels.data() + static_cast<std::size_t>(y) * ids.width;
    for (int x = 0; x < ids.width; ++x)
      if (before[2 * x] < 0.0f && before[2 * x + 1] > 0.0f) to[x] = blended[2 * x];
  }
  return objectIds;
}

void Renderer::Impl::drawAovLayers(Prepared& prepared, const ViewCamera& camera,
                                   const LightingAmbience& ambient, const RenderSettings& settings,
                                   const std::vector<std::uint8_t>& blendedOnly, FloatImage& aovs,
                                   StageTimes& times) {
  const int lightCount = static_cast<int>(prepared.shaded.size());
  const bool flip = camera.glRowOrder;
  const AovLayers& layers = settings.layers;
  if (!layers.any()) return;
  FrameTargets& layerTargets = keptTargets(layerTargets_, softwareRasterizer_, camera.width,
                                           camera.height, PassOutputs::Layers);
  LightingPass& layerPass = lightingPass(settings.shading, PassOutputs::Layers, prepared.features);
  // One layer pass, its `copies` (attachments 1 and 2) read into the AOV image; where only
  // blended surfaces cover a pixel, a second pass of those gives it theirs.
  auto runLayerPass = [&](int mode, int light, const std::vector<ChannelCopy>& copies) {
    PassParameters parameters;
    parameters.layerMode = mode;
    parameters.layerLight = light;
    ScopedStage stage(times, "layers");
    layerPass.render(prepared.gpu, camera, prepared.shaded, prepared.groups, transmittanceAtlas(),
                     ambient, layerTargets, parameters);
    readChannels(layerTargets, copies, flip, aovs);
    if (blendedOnly.empty()) return;
    parameters.blendedOnly = true;
    layerPass.render(prepared.gpu, camera, prepared.shaded, prepared.groups, transmittanceAtlas(),
                     ambient, layerTargets, parameters);
    FloatImage blended{camera.width, camera.height, {}, {}};
    std::vector<ChannelCopy> toBlended;
    for (const ChannelCopy& copy : copies) {
      toBlended.push_back(
          {copy.attachment, copy.from, copy.count, static_cast<int>(blended.channels.size())});
      blended.channels.resize(blended.channels.size() + static_cast<std::size_t>(copy.count));
    }
    blended.pixels.resize(static_cast<std::size_t>(camera.width) * camera.height *
                          blended.channels.size());
    readChannels(layerTargets, toBlended, flip, blended);
    const std::size_t stride = aovs.channels.size(), blendedStride = blended.channels.size();
    for (std::size_t i = 0; i < blendedOnly.size(); ++i) {
      if (!blendedOnly[i]) continue;
      for (std::size_t k = 0; k < copies.size(); ++k)
        std::copy_n(blended.pixels.begin() + i * blendedStride + toBlended[k].to, copies[k].count,
                    aovs.pixels.begin() + i * stride + copies[k].to);
    }
  };
  int next = kFixedAovChannels + lightCount;
  if (layers.albedo || layers.roughness || layers.metallic || layers.objectId ||
      layers.materialId) {
    // Attachment 1: albedo.rgb, roughness; 2: metallic, objectId, materialId.
    std::vector<ChannelCopy> copies;
    if (layers.albedo) copies.push_back({1, 0, 3, std::exchange(next, next + 3)});
    if (layers.roughness) copies.push_back({1, 3, 1, next++});
    if (layers.metallic) copies.push_back({2, 0, 1, next++});
    if (layers.objectId) copies.push_back({2, 1, 1, next++});
    if (layers.materialId) copies.push_back({2, 2, 1, next++});
    runLayerPass(0, -1, copies);
  }
  if (layers.occlusion) ++next;  // the AOV pass's (drawAovs())
  if (layers.diffuse || layers.specular) {
    for (int light = 0; light < lightCount; ++light) {
      std::vector<ChannelCopy> copies;  // attachment 1: the light's diffuse; 2: its specular
      if (layers.diffuse) copies.push_back({1, 0, 3, std::exchange(next, next + 3)});
      if (layers.specular) copies.push_back({2, 0, 3, std::exchange(next, next + 3)});
      runLayerPass(1, light, copies);
    }
  }
}

Frame Renderer::Impl::render(const Scene& scene, const std::vector<Light>& requested,
                             const Ambience& ambience, const ViewCamera& camera,
                             const RenderSettings& settings, StageTimes& times) {
  const bool lit = drawsLitFrame(settings);
  LightingAmbience ambient{ambience.ambient, {}, {}};
  std::vector<Light> withSun;
  if (lit && ambience.environment) {
    // Read and prefiltered once for a batch over the same image (EnvironmentCache); an image
    // that cannot be read is refused before the textures are made. Its sun, taken out of it,
    // joins the lights, unless one of them has its name.
    ScopedStage stage(times, "environment");
    ambient.environment = environmentCache_.bind(*ambience.environment);
    const auto named = [](const Light& light) { return light.name == kEnvironmentSunName; };
    if (ambient.environment.sun && std::none_of(requested.begin(), requested.end(), named)) {
      withSun = requested;
      withSun.push_back(*ambient.environment.sun);
    }
  }
  if (lit && ambience.ambientOcclusion) {
    AmbientOcclusion occlusion = *ambience.ambientOcclusion;
    occlusion.radius = effectiveRadius(occlusion, scene.bounds);
    ambient.occlusion = occlusion;
  }
  const std::vector<Light>& lights = withSun.empty() ? requested : withSun;
  // Everything else that can be refused is refused here, before any GL allocation.
  FramePlan plan = planFrame(scene, lights, camera, settings, limits_);
  checkAovMemory(lights, camera, settings);
  Frame frame;
  frame.warnings = std::move(plan.warnings);

  ScopedStage shaders(times, "shaders");
  LightingFeatures features = lightingFeatures(lights, settings.debugView);
  setShadowSlots(plan.shadows, features);
  features.facingLightLoop = features.facingLightLoop && ballot_;
  const std::vector<bool> translucent = translucentShadowLights(lights, scene);
  features.translucentShadows =
      std::find(translucent.begin(), translucent.end(), true) != translucent.end();
  features.environment = ambient.environment.textures != nullptr;
  features.ambientOcclusion = ambient.occlusion.has_value();
  const PassOutputs beautyOutputs = omnishadow::beautyOutputs(scene, settings);
  if (lit) lightingPass(settings.shading, beautyOutputs, features);  // made once per feature set
  shaders.stop();

  ScopedStage upload(times, "upload");
  SceneDigests& digests = sceneDigests(scene);
  const std::vector<MeshDigests>& meshes = digests.meshes;
  Prepared prepared(scene, &textureCache_, &geometryCache_, &meshes, &digests.images);
  textureCache_.dropUnused();  // an earlier scene's textures this one did not take
  prepared.features = features;
  prepared.beautyOutputs = beautyOutputs;
  frame.warnings.insert(frame.warnings.end(), prepared.gpu.warnings().begin(),
                        prepared.gpu.warnings().end());
  const bool finishEachStage = settings.finishEachStage.value_or(softwareRasterizer_);
  endStage(times, "upload", finishEachStage);
  upload.stop();
  if (!lit) {
    // Masks alone: the id pass reads no light and no shadow map. The shadow cache stays as the
    // last lit frame left it.
    for (const Light& light : lights) prepared.shaded.push_back({&light, nullptr});
    prepared.translucent.assign(lights.size(), false);
    aovTargets_.reset();
    layerTargets_.reset();
    frame.objectIds = drawObjectIds(prepared, camera, ambient, settings, times);
    gl::checkErrors("reading back the frame");
    return frame;
  }
  {
    ScopedStage variants(times, "shaders");  // the beauty's material variants
    lightingPass(settings.shading, beautyOutputs, features).compileMaterialVariants(prepared.gpu);
  }

  ScopedStage shadowStage(times, "shadow maps");
  renderShadows(prepared, std::move(plan.shadows), scene, lights, settings,
                shadowFingerprint(scene, meshes, &digests.casterImages), &frame);
  endStage(times, "shadow maps", finishEachStage);
  shadowStage.stop();

  if (settings.readShadowMaps) frame.shadowMaps = readShadowMaps(prepared, times);
  if (settings.readShadowMaps) frame.planarShadowMaps = readPlanarShadowMaps(prepared, times);
  drawImages(prepared, lights, camera, ambient, settings, plan.debugLight, frame, times);
  if (settings.lightViewSize > 0) {
    ScopedStage stage(times, "light views");
    frame.lightViews = drawLightViews(prepared, camera, ambient, settings);
  }
  gl::checkErrors("reading back the frame");
  shadowCache_ = ShadowCache{prepared.fingerprint, prepared.everyCaster, std::move(prepared.atlas),
                             lights, std::move(prepared.groups)};
  return frame;
}

std::vector<ShadowMapDump> Renderer::Impl::readShadowMaps(const Prepared& prepared,
                                                          StageTimes& times) {
  ScopedStage readback(times, "readback");
  std::vector<ShadowMapDump> dumps;
  for (const ShadedLight& s : prepared.shaded)
    if (s.shadow && s.light->type == LightType::Point)
      dumps.push_back({s.light->name, s.shadow->far,
                       readCubeDistances(prepared.groups[s.shadow->group], *s.shadow)});
  return dumps;
}

std::vector<PlanarShadowMapDump> Renderer::Impl::readPlanarShadowMaps(const Prepared& prepared,
                                                                      StageTimes& times) {
  ScopedStage readback(times, "readback");
  std::vector<PlanarShadowMapDump> dumps;
  for (const ShadedLight& s : prepared.shaded) {
    if (!s.shadow || s.light->type == LightType::Point) continue;
    const bool directional = s.light->type == LightType::Directional;
    for (int layer = 0; layer < s.shadow->layerCount; ++layer)
      dumps.push_back(
          {s.light->name, directional ? "cascade" + std::to_string(layer) : "spot",
           s.light->shadow.resolution, directional ? s.shadow->far - s.shadow->near : s.shadow->far,
           readPlanarDistances(prepared.groups[s.shadow->group], *s.shadow, layer, directional)});
  }
  return dumps;
}

Renderer::Impl::SceneDigests& Renderer::Impl::sceneDigests(const Scene& scene) {
  if (scene.revision == 0 || scene.revision != sceneDigests_.revision ||
      sceneDigests_.meshes.size() != scene.meshes.size() ||
      sceneDigests_.images.size() != scene.images.size())
    sceneDigests_ = {scene.revision, meshDigests(scene), ImageDigests(scene.images.size()),
                     ImageHashes(scene.images.size())};
  return sceneDigests_;
}

void Renderer::Impl::choosePrepass(std::uint64_t scene, DepthPrepass requested,
                                   const ViewCamera& camera,
                                   const std::function<OverdrawCounts()>& estimate,
                                   PassParameters& parameters) {
  if (requested != DepthPrepass::Auto) {  // the auto choice of the scene's frames stays as it was
    parameters.depthPrepass = requested == DepthPrepass::On;
    return;
  }
  if (!prepassSupported_) {
    parameters.depthPrepass = false;
    return;
  }
  PrepassChoice& choice = prepassChoice_;
  const glm::mat4 viewProjection = camera.projection * camera.view;
  const bool moved = viewProjection != choice.viewProjection || camera.width != choice.width ||
                     camera.height != choice.height;
  // The estimate costs up to 5 ms a frame on 100k triangles (31 on 1M), so a camera that moves
  // every frame is estimated for every eighth; occlusion counts in a frame that draws the
  // pre-pass to count cost more (Sundial's lighting 3 ms, test_room's 10, docs/performance.md).
  if (scene == 0 || choice.scene != scene || (moved && choice.frames >= kPrepassReestimate))
    choice = {
        scene, viewProjection, camera.width, camera.height, 0, prepassSparesTooLittle(estimate())};
  ++choice.frames;
  parameters.depthPrepass = !choice.skip;
}

// Shading up to 10% more fragments costs less than drawing every opaque triangle once more
// (Box: the pre-pass 0.3 ms against 7 ms of shading; WhackAMole, 86k triangles, 5 against 38).
// Sundial lets 5.5% more through the pre-pass than it shades, and its steady lighting took
// 13.9 ms with the pre-pass against 12.9 without (with three lights, 23.2 against 22.1); the
// Cornell box (58% more) keeps it. Beyond that share it still costs more than it spares where
// the scene has many triangles for the fragments spared: with its surfaces drawn nearest first,
// test_room (102k triangles) spares 82k fragments, 11%, and its steady lighting took 60-64 ms
// without the pre-pass against 64-72 with it; CesiumMilkTruck (3.6k triangles) spares 20k,
// 13%, and is a little faster with it (docs/performance.md).
bool Renderer::Impl::prepassSparesTooLittle(const OverdrawCounts& counts) {
  const std::uint64_t spared = counts.passed > counts.covered ? counts.passed - counts.covered : 0;
  return spared * 100 <= counts.covered * kPrepassMinOverdraw ||
         spared <= counts.triangles * kPrepassMinSparedPerTriangle;
}

void Renderer::Impl::drawImages(Prepared& prepared, const std::vector<Light>& lights,
                                const ViewCamera& camera, const LightingAmbience& ambient,
                                const RenderSettings& settings, int debugLight, Frame& frame,
                                StageTimes& times) {
  const bool objectIdPass = drawsObjectIdPass(settings);
  if (!settings.aovs) aovTargets_.reset();
  if (!settings.aovs || !settings.layers.any()) layerTargets_.reset();
  if (!objectIdPass) idTargets_.reset();
  if (settings.aovs) {
    FloatImage aovs{camera.width,
                    camera.height,
                    aovChannels(lights, settings.layers, prepared.translucent),
                    {}};
    // Zeroed: a channel no pass writes (a light without translucent casters) stays 0.
    aovs.pixels.resize(
        static_cast<std::size_t>(camera.width) * camera.height * aovs.channels.size(), 0.0f);
    drawAovs(prepared, camera, ambient, settings, aovs, times);
    frame.aovs = std::move(aovs);
  }
  if (drawsBeauty(settings)) {
    PassParameters parameters;
    parameters.debugView = settings.debugView;
    parameters.debugLight = debugLight;
    const LightingPass& pass =
        lightingPass(settings.shading, prepared.beautyOutputs, prepared.features);
    choosePrepass(
        prepared.fingerprint, settings.depthPrepass, camera,
        [&] { return pass.estimateOpaqueFragments(prepared.gpu, prepared.scene.meshes, camera); },
        parameters);
    frame.depthPrepass = parameters.depthPrepass;
    IdPixels ids;  // written beside the float beauty (BeautyIds)
    if (writesSrgb8(prepared.beautyOutputs))
      drawSrgb8(prepared, camera, ambient, settings, parameters, frame, times);
    else if (const FloatBeautyEncoding encoder = floatBeautyEncoder(settings);
             encoder != FloatBeautyEncoding::Caller)
      drawResolvedSrgb8(encoder, prepared, camera, ambient, settings, parameters, frame, times,
                        ids);
    else
      frame.beauty =
          drawAntialiasedBeauty(prepared, camera, ambient, settings, parameters, times, ids);
    if (objectIdPass && !frame.objectIds)
      frame.objectIds = drawObjectIds(prepared, camera, ambient, settings, times, std::move(ids));
    return;
  }
  // The AOV pass already drew the beauty.
  frame.beauty = FloatImage{camera.width, camera.height, {"R", "G", "B", "A"}, {}};
  frame.beauty.pixels.resize(static_cast<std::size_t>(camera.width) * camera.height * 4);
  const std::size_t stride = frame.aovs->channels.size();
  for (std::size_t i = 0; i < frame.beauty.pixels.size() / 4; ++i)
    for (int c = 0; c < 4; ++c) frame.beauty.pixels[i * 4 + c] = frame.aovs->pixels[i * stride + c];
}

std::vector<LightView> Renderer::Impl::drawLightViews(Prepared& prepared, const ViewCamera& camera,
                                                      const LightingAmbience& ambient,
                                                      const RenderSettings& settings) {
  std::vector<LightView> views;
  for (const ShadedLight& s : prepared.shaded) {
    if (s.light->type != LightType::Point) {
      if (!s.shadow) continue;  // only a shadowed light has a map to look through
      for (int layer = 0; layer < s.shadow->layerCount; ++layer) {
        const ViewCamera view =
            planarLightCamera(*s.light, s.shadow->viewProjection[layer], s.shadow->near,
                              s.shadow->far, settings.lightViewSize);
        PassParameters parameters;
        parameters.cascadeView = &camera.view;
        views.push_back(
            {s.light->name, CubeFace::PosX,
             drawBeauty(prepared, view, ambient, settings, parameters, nullptr),
             s.light->type == LightType::Spot ? "spot" : "cascade" + std::to_string(layer)});
      }
      continue;
    }
    for (int face = 0; face < kCubeFaceCount; ++face) {
      ViewCamera view;
      view.width = view.height = settings.lightViewSize;
      view.eye = s.light->position;
      view.view = cubeFaceView(static_cast<CubeFace>(face), s.light->position);
      view.projection = reversedPerspective(
          glm::radians(90.0f), 1.0f, effectiveShadowNear(*s.light, prepared.scene.bounds), 0.0f);
      view.glRowOrder = true;
      PassParameters parameters;
      parameters.cascadeView = &camera.view;  // directional cascades stay those of the frame
      views.push_back({s.light->name, static_cast<CubeFace>(face),
                       drawBeauty(prepared, view, ambient, settings, parameters, nullptr)});
    }
  }
  return views;
}

std::vector<CubeDistances> Renderer::Impl::renderShadowDistances(const Scene& scene,
                                                                 const std::vector<Light>& lights,
                                                                 ShadowPassStrategy strategy,
                                                                 bool parallel) {
  Prepared prepared(scene, nullptr, nullptr, nullptr, nullptr);
  RenderSettings settings;
  settings.shadowPass = strategy;
  settings.parallelShadowMaps = parallel;
  settings.readShadowMaps = true;
  ShadowAtlasPlan plan =
      planShadowAtlas(lights, ViewCamera{}, scene.bounds, ShadowLimits{limits_.maxArrayLayers});
  renderShadows(prepared, std::move(plan), scene, lights, settings, std::nullopt, nullptr);
  std::vector<CubeDistances> out;
  for (const ShadedLight& s : prepared.shaded)
    if (s.shadow && s.light->type == LightType::Point)
      out.push_back(readCubeDistances(prepared.groups[s.shadow->group], *s.shadow));
  for (ShadowGroupTextures& group : prepared.groups) shadowTextures_.give(std::move(group));
  return out;
}

double Renderer::Impl::prepare(const std::vector<Light>& lights, int width, int height,
                               const RenderSettings& settings, double budgetMiB,
                               double minimumMiB) {
  // The checks render() makes, on a stand-in scene: the shadow groups and the frame targets
  // depend on the lights and the frame size, not on the scene.
  Scene standIn;
  standIn.bounds.extend(glm::vec3(-1.0f));
  standIn.bounds.extend(glm::vec3(1.0f));
  ViewCamera camera;
  camera.width = width;
  camera.height = height;
  FramePlan plan;
  try {
    plan = planFrame(standIn, lights, camera, settings, limits_);
  } catch (const InputError&) {
    return 0.0;  // render() says why
  }
  if (!drawsLitFrame(settings)) return 0.0;  // masks alone: no shadow maps, no beauty
  const bool beauty = drawsBeauty(settings);
  // Where the lighting pass may encode the beauty, the scene decides (blended surfaces need the
  // float one): both are prepared.
  const bool srgb8 = beauty && encodesSrgb8(Scene{}, settings);
  const PassOutputs srgb8Outputs = beautyOutputs(Scene{}, settings);
  const PassOutputs floatOutputs = floatBeautyOutputs(settings);
  const double bytes = plan.shadows.bytes +
                       (beauty ? FrameTargets::bytes(width, height, floatOutputs) : 0.0) +
                       (srgb8 ? FrameTargets::bytes(width, height, srgb8Outputs) : 0.0);
  if (bytes > budgetMiB * 1024.0 * 1024.0 || bytes < minimumMiB * 1024.0 * 1024.0) return 0.0;
  for (const ShadowGroupPlan& group : plan.shadows.groups) {
    ShadowGroupTextures textures = shadowTextures_.take(group);
    clearShadowTextures(textures);
    shadowTextures_.give(std::move(textures));
  }
  if (srgb8) beautyTargets(width, height, srgb8Outputs);
  if (beauty) beautyTargets(width, height, floatOutputs);
  glFlush();  // the clears start in the rasterizer threads now
  return bytes;
}

double Renderer::Impl::frameBytes(const Scene& scene, const std::vector<Light>& lights,
                                  const ViewCamera& camera, const RenderSettings& settings) const {
  FramePlan plan;
  try {
    plan = planFrame(scene, lights, camera, settings, limits_);
  } catch (const InputError&) {
    return 0.0;  // render() says why
  }
  if (!drawsLitFrame(settings)) return 0.0;
  double bytes = plan.shadows.bytes;
  if (drawsBeauty(settings)) {
    const PassOutputs outputs = beautyOutputs(scene, settings);
    // What is read back a pixel: RGB bytes, or the float RGBA; encoded on the GPU, its RGBA8UI
    // target and the RGB bytes; encoded on the CPU in bands, the RGB bytes (and a few bands).
    const FloatBeautyEncoding encoder = floatBeautyEncoder(settings);
    const double readback = writesSrgb8(outputs) || encoder == FloatBeautyEncoding::CpuInBands ? 3.0
                            : encoder == FloatBeautyEncoding::Gpu ? 4.0 + 3.0
                                                                  : 16.0;
    bytes += FrameTargets::bytes(camera.width, camera.height, outputs) +
             static_cast<double>(camera.width) * camera.height * readback;
  }
  return bytes;
}

// Every entry that makes GL calls makes this renderer's context current first: a thread may
// hold several renderers (a Python session that makes a new one before the old one goes), and
// GL calls go to whichever context was made current last, another renderer's or none.
Renderer::Renderer(const ContextOptions& options) : impl_(std::make_unique<Impl>(options)) {}

Renderer::~Renderer() {
  // Its GL objects are deleted in its own context, not in the one current now, whose objects
  // may have the same names.
  try {
    impl_->context().makeCurrent();
  } catch (const RenderError&) {
    // Nothing to delete them in: they go with the context.
  }
}

const RenderLimits& Renderer::limits() const {
  return impl_->limits();
}

const std::string& Renderer::platformDescription() const {
  return impl_->context().platformDescription();
}

std::string Renderer::glDescription() const {
  impl_->context().makeCurrent();
  return impl_->context().glDescription();
}

Frame Renderer::render(const Scene& scene, const std::vector<Light>& lights,
                       const Ambience& ambience, const ViewCamera& camera,
                       const RenderSettings& settings, StageTimes& times) {
  impl_->context().makeCurrent();
  return impl_->render(scene, lights, ambience, camera, settings, times);
}

std::vector<CubeDistances> Renderer::renderShadowDistances(const Scene& scene,
                                                           const std::vector<Light>& lights,
                                                           ShadowPassStrategy strategy,
                                                           bool parallelShadowMaps) {
  impl_->context().makeCurrent();
  return impl_->renderShadowDistances(scene, lights, strategy, parallelShadowMaps);
}

void Renderer::prepareEnvironment(const EnvironmentLight& environment) {
  impl_->context().makeCurrent();
  impl_->prepareEnvironment(environment);
}

double Renderer::prepare(const std::vector<Light>& lights, int width, int height,
                         const RenderSettings& settings, double budgetMiB, double minimumMiB) {
  impl_->context().makeCurrent();
  return impl_->prepare(lights, width, height, settings, budgetMiB, minimumMiB);
}

double Renderer::frameBytes(const Scene& scene, const std::vector<Light>& lights,
                            const ViewCamera& camera, const RenderSettings& settings) const {
  return impl_->frameBytes(scene, lights, camera, settings);
}

}  // namespace omnishadow
