#pragma once

#include <optional>
#include <string>

namespace omnishadow {

enum class Shading { Pbr, Phong };

// What replaces the beauty image (--debug-view). The values are part of the C++/GLSL contract
// (renderer/passes/shader_contract.h injects them into lighting.frag).
enum class DebugView { None = 0, Shadow, Depth, Normals, Albedo, LightCount, Cascade, Occlusion };

// How a point light's six cube faces are rendered (--shadow-pass). All of them write the same
// texels; they differ in speed, which depends on the driver (docs/performance.md).
enum class ShadowPassStrategy {
  Auto,       // the renderer's choice for its driver (today always Six, see shadow_pass.cpp)
  Six,        // one pass per face, objects culled per face on the CPU
  Geometry,   // one pass, a geometry shader copies each triangle to six layers (the classic)
  Instanced,  // one pass, instances pick the face and write gl_Layer from the vertex shader;
              // objects are culled per face too (runs of faces per object)
  Batched,    // one pass for all the frame's point lights that share a shadow texture and
              // raster settings: as Instanced, the instance picking a layer of the whole
              // texture, so that nothing is attached between lights (for GPU drivers, which
              // pay per light; vsm lights and spot and directional lights as Six)
};

const char* toString(ShadowPassStrategy strategy);
// "auto", "six", "geometry", "instanced" or "batched"; anything else is Auto (the CLI checks the
// spelling).
ShadowPassStrategy parseShadowPassStrategy(const std::string& name);
// Whether `name` is one of the spellings above (the Python module checks its argument with it;
// the CLI lists them in its option).
bool isShadowPassStrategyName(const std::string& name);

// Where the PNG bytes of a beauty drawn in float are made (RenderSettings::srgb8Exposure with
// blended or see-through surfaces, which the lighting pass cannot encode itself). The bytes are
// the same either way.
enum class FloatBeautyEncoding {
  // On the GPU, except on a software rasterizer (llvmpipe), where the float target's read back
  // is a copy in memory and the pass costs more than it saves (1280x720: readback 1.5 -> 6.2
  // ms): there on the CPU while the rows are read back (CpuInBands).
  Auto,
  // A pass after the lighting encodes the float target into an 8-bit one, read back at a quarter
  // of the bytes (an H200, Sundial at 1280x720: readback 5.9-8.1 -> 2.2-2.5 ms); Frame::srgb8.
  Gpu,
  // The float target read back a band of rows at a time, each band encoded on the CPU while the
  // next is read (llvmpipe, Sundial at 1280x720: a process's first frame's readback 9.7 -> 2.7
  // ms, its PNG encoding 11.6 -> 8.7; a later frame's readback 1.5 -> 2.9, which now includes
  // the encoding); Frame::srgb8.
  CpuInBands,
  Caller,  // the float beauty read back, Frame::beauty, encoded by the caller (toSrgb8())
};

// Whether the beauty's opaque surfaces first write their depth alone, so that the light loop
// runs once a pixel (--depth-prepass). The picture is the same either way; the speed depends on
// how many surfaces hide others and on the driver (docs/performance.md).
enum class DepthPrepass {
  Auto,  // llvmpipe: drawn, and dropped for a scene whose second frame counts little overdraw;
         // other drivers: not drawn (an NVIDIA driver failed its depth test, see lighting_pass.h)
  On,    // always drawn
  Off,   // never drawn
};

const char* toString(DepthPrepass prepass);
// "auto", "on" or "off"; anything else is Auto (callers check the spelling with
// isDepthPrepassName()).
DepthPrepass parseDepthPrepass(const std::string& name);
bool isDepthPrepassName(const std::string& name);

// RenderSettings::finishEachStage from its spelling (--finish-each-stage): "on" true, "off"
// false, anything else unset (auto; callers check the spelling with isFinishEachStageName()).
std::optional<bool> parseFinishEachStage(const std::string& name);
bool isFinishEachStageName(const std::string& name);

// Optional AOV layers (--aov-layers), appended to Frame::aovs after the fixed channels.
struct AovLayers {
  bool albedo = false;      // albedo.R/G/B
  bool roughness = false;   // roughness
  bool metallic = false;    // metallic
  bool diffuse = false;     // diffuse.<light>.R/G/B
  bool specular = false;    // specular.<light>.R/G/B
  bool objectId = false;    // objectId: index into Scene::instances, -1 = background
  bool materialId = false;  // materialId: index into Scene::materials (the default material is
                            // Scene::materials.size()), -1 = background
  // occlusion: the share of the ambient and environment light the surface receives (its
  // occlusion texture times the lights file's ambient_occlusion; --debug-view occlusion)
  bool occlusion = false;
  bool any() const {
    return albedo || roughness || metallic || diffuse || specular || objectId || materialId ||
           occlusion;
  }
};

struct RenderSettings {
  Shading shading = Shading::Pbr;
  bool aovs = false;   // fill Frame::aovs
  AovLayers layers{};  // with aovs
  // Without aovs: fill Frame::objectIds, the objectId layer alone (annotation masks), from a
  // pass that draws no light instead of the AOV pass. With aovs, ask for layers.objectId.
  bool objectIds = false;
  // False: the caller needs no picture. A frame that then asks for objectIds alone (masks
  // without an image: no AOVs, shadow map dumps, light views or debug view, which all need the
  // lit frame) draws neither shadow maps nor the beauty, and Frame::beauty and Frame::srgb8
  // stay empty; any other frame draws the beauty anyway.
  bool beauty = true;
  DebugView debugView = DebugView::None;
  std::string debugLight{};     // DebugView::Depth: light name; empty = the first shadowed one
                                // (DebugView::Cascade: the first shadowed directional one)
  bool readShadowMaps = false;  // fill Frame::shadowMaps
  int lightViewSize = 0;        // > 0: fill Frame::lightViews with images of this size
  // Shadow maps may use at most this much memory (MiB); more is an InputError before any GL
  // allocation, naming the size needed.
  double maxShadowMemoryMiB = 4096.0;
  // With aovs (or objectIds): the AOV pass's render targets and the AOV image together (the
  // CLI gives both bounds --max-memory); more is an InputError before any GL allocation.
  double maxAovMemoryMiB = 4096.0;
  ShadowPassStrategy shadowPass = ShadowPassStrategy::Auto;
  DepthPrepass depthPrepass = DepthPrepass::Auto;  // of the beauty
  // Where the GL is a software rasterizer (llvmpipe) and a frame draws two or more lights' maps,
  // half of them are drawn in a second GL context at once (passes/shadow_worker.h). The maps,
  // and so the pictures, are the same either way; false draws every map in the one context.
  bool parallelShadowMaps = true;
  int antialiasing = 1;  // --aa: beauty samples per pixel, 1, 4, 8 or 16 (render/antialiasing.h)
  // Set, for callers that want the beauty only as 8-bit sRGB (a PNG): where it can (no AOVs, no
  // --aa, no blended surfaces in the scene) the lighting pass encodes the beauty times
  // 2^srgb8Exposure itself, into an 8-bit target a quarter of the float one's size to clear and
  // read back, and render() fills Frame::srgb8 instead of Frame::beauty; with blended or
  // see-through surfaces, the renderer encodes the float target (floatBeautyEncoding).
  std::optional<float> srgb8Exposure{};
  // With srgb8Exposure, for the frames the lighting pass cannot encode itself.
  FloatBeautyEncoding floatBeautyEncoding = FloatBeautyEncoding::Auto;
  // Whether the GPU finishes the upload's and the shadow maps' work before the next stage is
  // submitted, so that each stage's time (StageTimes) holds its own GPU work. False: the
  // lighting's CPU work (its light clusters, its draws) runs while the GPU still draws the
  // maps, and the lighting's wait holds what is left of theirs. Unset: true on a software
  // rasterizer, whose threads are busy with the maps anyway (no gain measured there), false on
  // GPUs. The pictures are the same either way.
  std::optional<bool> finishEachStage{};
};

// Asks for each pixel's objectId (annotation masks): the AOVs' objectId layer when `settings`
// asks for AOVs, else Frame::objectIds from a pass of its own.
void requestObjectIds(RenderSettings& settings);

// Whether the frame draws its shadow maps and the beauty: every frame except one that asks for
// objectIds alone (RenderSettings::beauty).
bool drawsLitFrame(const RenderSettings& settings);

// What the device allows, queried once when the renderer is made. Frame planning checks a
// frame against these before any GL call.
struct RenderLimits {
  int maxCubeMapSize = 16384;  // GL_MAX_CUBE_MAP_TEXTURE_SIZE
  int maxTextureSize = 16384;  // GL_MAX_TEXTURE_SIZE
  int maxArrayLayers = 2048;   // GL_MAX_ARRAY_TEXTURE_LAYERS
  // Texels of the largest square RGBA32F frame target the GL will allocate (proxy textures):
  // llvmpipe also limits a texture's bytes, so 12000x12000 fails below GL_MAX_TEXTURE_SIZE.
  long long maxFrameTexels = 16384LL * 16384LL;
};

}  // namespace omnishadow
