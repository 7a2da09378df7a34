#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "renderer/camera.h"
#include "renderer/egl_context.h"
#include "renderer/image_writer.h"
#include "renderer/light.h"
#include "renderer/lighting_pass.h"
#include "renderer/scene.h"
#include "renderer/stage_timer.h"

namespace omnishadow {

struct RenderSettings {
  Shading shading = Shading::Pbr;
  bool aovs = false;  // fill Frame::aovs
};

// What one render produces, read back to the CPU; first row = top of the picture.
struct Frame {
  FloatImage beauty;  // R,G,B,A: linear, premultiplied, A = coverage
  // R,G,B,A, P.X,P.Y,P.Z, N.X,N.Y,N.Z, Z, visibility.<light> per light (README, "Outputs").
  std::optional<FloatImage> aovs;
  std::vector<std::string> warnings;
};

// Shadow settings a light is actually rendered with: its `far` filled in when automatic.
float effectiveShadowFar(const Light& light, const Bounds& sceneBounds);

// Owns the headless GL context and the compiled passes; renders frames of any scene. Not
// thread-safe: use it from the thread that created it.
class Renderer {
 public:
  explicit Renderer(const ContextOptions& options);
  ~Renderer();

  const EglContext& context() const { return *context_; }

  // Renders the scene's lights merged with `lights` (lights must already be merged and named
  // uniquely). Stage times go to `times`: upload, shadow maps, lighting, readback.
  Frame render(const Scene& scene, const std::vector<Light>& lights, const glm::vec3& ambient,
               const ViewCamera& camera, const RenderSettings& settings, StageTimes& times);

  // Depth cube maps of the shadowed point lights, as distances, e.g. for tests and dumps.
  std::vector<CubeDistances> renderShadowDistances(const Scene& scene,
                                                   const std::vector<Light>& lights);

 private:
  LightingPass& lightingPass(const RenderSettings& settings);

  std::unique_ptr<EglContext> context_;
  std::unique_ptr<ShadowPass> shadowPass_;
  std::vector<std::pair<std::pair<Shading, bool>, std::unique_ptr<LightingPass>>> lightingPasses_;
};

}  // namespace omnishadow
