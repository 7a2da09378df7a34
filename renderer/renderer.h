#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/camera.h"
#include "renderer/cube_distances.h"
#include "renderer/egl_context.h"
#include "renderer/image_writer.h"
#include "renderer/light.h"
#include "renderer/lighting_pass.h"
#include "renderer/scene.h"
#include "renderer/shadow_atlas.h"
#include "renderer/shadow_pass.h"
#include "renderer/stage_timer.h"

namespace omnishadow {

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
  bool any() const {
    return albedo || roughness || metallic || diffuse || specular || objectId || materialId;
  }
};

struct RenderSettings {
  Shading shading = Shading::Pbr;
  bool aovs = false;  // fill Frame::aovs
  AovLayers layers;   // with aovs
  DebugView debugView = DebugView::None;
  std::string debugLight;       // DebugView::Depth: light name; empty = the first shadowed one
  bool readShadowMaps = false;  // fill Frame::shadowMaps
  int lightViewSize = 0;        // > 0: fill Frame::lightViews with images of this size
  // Shadow maps may use at most this much memory (MiB); more is an InputError before any GL
  // allocation, naming the size needed.
  double maxShadowMemoryMiB = 4096.0;
  ShadowPassStrategy shadowPass = ShadowPassStrategy::Auto;
};

// A point light's shadow map as the lighting pass sampled it.
struct ShadowMapDump {
  std::string light;
  float far = 0.0f;
  CubeDistances distances;
};

// The lit scene seen from one cube face of a point light, in GL texel layout like the dumps.
struct LightView {
  std::string light;
  CubeFace face;
  FloatImage beauty;
};

// What one render produces, read back to the CPU; first row = top of the picture.
struct Frame {
  FloatImage beauty;  // R,G,B,A: linear, premultiplied, A = coverage
  // R,G,B,A, P.X,P.Y,P.Z, N.X,N.Y,N.Z, Z, visibility.<light> per light (README, "Outputs"),
  // then the requested layers.
  std::optional<FloatImage> aovs;
  std::vector<ShadowMapDump> shadowMaps;
  std::vector<LightView> lightViews;
  std::vector<std::string> warnings;
  // Shadowed lights whose maps were rendered for this frame, and those kept from the previous
  // render of the same scene (point and spot lights whose maps cannot have changed).
  int shadowMapsRendered = 0;
  int shadowMapsReused = 0;
};

// Owns the headless GL context and the compiled passes; renders frames of any scene. Not
// thread-safe: use it from the thread that created it.
class Renderer {
 public:
  explicit Renderer(const ContextOptions& options);
  ~Renderer();

  const EglContext& context() const { return *context_; }

  // Renders the scene with `lights` (already merged and uniquely named). Stage times go to
  // `times`: shaders, upload, shadow maps, lighting, readback. Throws InputError for settings
  // the scene cannot satisfy (too many shadowed lights, an unknown --debug-light).
  Frame render(const Scene& scene, const std::vector<Light>& lights, const glm::vec3& ambient,
               const ViewCamera& camera, const RenderSettings& settings, StageTimes& times);

  // Depth cube maps of the shadowed point lights, as distances, e.g. for tests.
  std::vector<CubeDistances> renderShadowDistances(
      const Scene& scene, const std::vector<Light>& lights,
      ShadowPassStrategy strategy = ShadowPassStrategy::Auto);

  // The strategy `auto` resolves to on this context.
  ShadowPassStrategy defaultShadowPass() const;

 private:
  struct Prepared;
  LightingPass& lightingPass(Shading shading, PassOutputs outputs,
                             const LightingFeatures& features);
  void renderShadows(Prepared& prepared, const Scene& scene, const std::vector<Light>& lights,
                     const ViewCamera& camera, const RenderSettings& settings, bool useCache,
                     Frame* frame);
  FloatImage drawBeauty(Prepared& prepared, const ViewCamera& camera, const glm::vec3& ambient,
                        const RenderSettings& settings, const PassParameters& parameters,
                        StageTimes* times);
  void drawAovs(Prepared& prepared, const ViewCamera& camera, const glm::vec3& ambient,
                const RenderSettings& settings, FloatImage& aovs, StageTimes& times);

  std::unique_ptr<EglContext> context_;
  std::unique_ptr<ShadowPass> shadowPass_;
  std::unique_ptr<class VsmFilter> vsmFilter_;
  ShadowTexturePool shadowTextures_;
  // The last frame's shadow maps, kept for the next render of the same scene (batch jobs of
  // one scene with several cameras): point and spot maps do not depend on the camera.
  struct ShadowCache {
    std::uint64_t scene = 0;
    ShadowAtlasPlan plan;
    std::vector<Light> lights;
    ShadowGroups groups;
  };
  std::optional<ShadowCache> shadowCache_;
  ShadowLimits shadowLimits_;
  int maxCubeSize_ = 0, maxTextureSize_ = 0;
  std::string glRenderer_;
  struct PassKey {
    Shading shading;
    PassOutputs outputs;
    LightingFeatures features;
  };
  std::vector<std::pair<PassKey, std::unique_ptr<LightingPass>>> lightingPasses_;
};

// Channel names of Frame::aovs for these lights and layers, in order.
std::vector<std::string> aovChannels(const std::vector<Light>& lights, const AovLayers& layers);

}  // namespace omnishadow
