#pragma once

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "renderer/core/context_options.h"
#include "renderer/core/stage_timer.h"
#include "renderer/render/frame.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/light.h"
#include "renderer/scene/scene.h"
#include "renderer/view/camera.h"
#include "renderer/view/cube_distances.h"

namespace omnishadow {

// Owns the headless GL context and the compiled passes; renders frames of any scene. Not
// thread-safe: use it from the thread that created it. This header is the whole interface to
// the GPU: nothing in it, or in what it includes, names a GL type.
class Renderer {
 public:
  // Throws RenderError when no context can be made, InputError for a --gpu that does not exist.
  explicit Renderer(const ContextOptions& options);
  ~Renderer();  // with impl_, neither copyable nor movable

  // What this device allows; planFrame() checks a frame against it.
  const RenderLimits& limits() const;
  // "EGL device 0 (NVIDIA ...)" or "EGL surfaceless platform", for --verbose.
  const std::string& platformDescription() const;
  // GL_VENDOR, GL_RENDERER, GL_VERSION as one line.
  std::string glDescription() const;

  // Renders the scene with `lights` (already merged and uniquely named) and `ambience` (a
  // constant ambient radiance, or a LightSetup's ambient and environment). Stage times go to
  // `times`: environment (an environment image read and prefiltered), shaders, upload, shadow
  // maps, lighting, readback. Throws InputError, before any GL call, for settings the scene
  // cannot satisfy on this device (planFrame()) and for an environment image that cannot be
  // read (a renderer keeps the last environment's textures: a batch reads its image once).
  Frame render(const Scene& scene, const std::vector<Light>& lights, const Ambience& ambience,
               const ViewCamera& camera, const RenderSettings& settings, StageTimes& times);

  // Does ahead of render() what needs no scene: allocates and clears the shadow maps of
  // `lights` and the beauty targets of a width x height frame, where the next render() that
  // needs them takes them. For time that would otherwise be spent waiting (the scene loading);
  // a render with other lights or another size leaves them unused. Nothing is prepared when it
  // would take more than `budgetMiB` or less than `minimumMiB`, or when render() would refuse
  // the lights or the size (render() reports that). Returns the bytes it prepared.
  double prepare(const std::vector<Light>& lights, int width, int height,
                 const RenderSettings& settings, double budgetMiB, double minimumMiB = 0.0);
  // Does ahead of render() what an environment light needs: reads and prefilters its image and
  // uploads the textures, which the next render() with the same environment takes. For time
  // spent waiting for the scene to load. An image that cannot be read is left for render() to
  // report.
  void prepareEnvironment(const EnvironmentLight& environment);
  // About the bytes render() allocates for the scene's frame: its shadow maps, the beauty's
  // targets and what the beauty is read back into; 0 where render() would refuse it. Makes no
  // GL call (the CLI's memory warm-up faults in as much ahead of the frame).
  double frameBytes(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
                    const RenderSettings& settings) const;

  // Depth cube maps of the shadowed point lights, as distances, with every caster drawn (as the
  // depth dumps hold them), e.g. for tests. `parallelShadowMaps`: as RenderSettings' (false:
  // one GL context draws every map, as on a GPU).
  std::vector<CubeDistances> renderShadowDistances(
      const Scene& scene, const std::vector<Light>& lights,
      ShadowPassStrategy strategy = ShadowPassStrategy::Auto, bool parallelShadowMaps = true);

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omnishadow
