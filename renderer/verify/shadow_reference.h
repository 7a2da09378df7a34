#pragma once

#include <glm/glm.hpp>
#include <memory>
#include <optional>

#include "renderer/scene/light.h"
#include "renderer/scene/scene.h"

namespace omnishadow {

// A surface found by a camera ray.
struct SurfaceHit {
  float t = 0.0f;
  glm::vec3 geometricNormal{0.0f};  // world space, unit length, as the triangle winds
  bool unlit = false;               // KHR_materials_unlit: lit by nothing, no shadow term
};

// Exact shadow rays against the scene's own triangles (Embree 3), to check the renderer's shadow
// maps against. Every instance is baked into world-space triangles. Alpha cut-outs follow the
// shadow pass: MASK materials below their cutoff and BLEND materials below 0.5 let light through,
// judged by baseColorFactor.a x COLOR_0.a x the nearest texel of the base color texture (with
// the texture's wrap modes). Triangles cast shadows from both sides. Queries are thread-safe.
//
// Lights with translucent shadows (castsTranslucentShadows(), in a scene with translucent
// casters) instead follow each shadow ray through every surface it crosses, front or back,
// multiplying the light by each translucent surface's surfaceTransmittance() (base color from
// the same nearest texel, sRGB decoded; the transmission texture's R at its nearest texel) and
// stopping at the first opaque or cut-out one.
class ShadowReference {
 public:
  // Throws RenderError when Embree cannot build the scene.
  explicit ShadowReference(const Scene& scene);
  ~ShadowReference();  // with impl_, neither copyable nor movable

  // Scene-scale length that keeps a ray off the surface it starts on: 1e-4 of the bounds'
  // diagonal.
  float epsilon() const { return epsilon_; }

  // Whether a shadow caster lies on the ray between tnear and tfar (tfar may be infinite).
  bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar) const;

  // The nearest surface the AOVs could show on this ray: blended surfaces are skipped (the AOVs
  // describe the opaque surface behind them), cut-out texels too.
  std::optional<SurfaceHit> intersect(const glm::vec3& origin, const glm::vec3& direction,
                                      float tnear, float tfar) const;

  // Fraction of the light reaching `point` (1 = fully lit), from rays leaving the surface at
  // point + normal * epsilon(); `normal` is the geometric normal on the light's side. A point or
  // spot light is a point, or with shadow.radius > 0 a disk of that radius facing the point; a
  // directional light is a direction, or with shadow.radius > 0 a cone of that angular radius
  // (radians). Disks and cones are sampled by `sourceSamples` stratified rays (rounded to a
  // square grid), the same every call.
  // With translucent shadows: the mean over RGB of transmittance().
  float visibility(const Light& light, const glm::vec3& point, const glm::vec3& normal,
                   int sourceSamples = 64) const;

  // The RGB fraction of the light reaching `point`, sampled as visibility() does; without
  // translucent shadows, visibility() in every channel.
  glm::vec3 transmittance(const Light& light, const glm::vec3& point, const glm::vec3& normal,
                          int sourceSamples = 64) const;

  // A ray crossing more translucent surfaces than this counts only these.
  static constexpr int kMaxTranslucentCrossings = 256;

 private:
  // Transmittance along one ray from tnear to tfar (translucent shadows).
  glm::vec3 rayTransmittance(const glm::vec3& origin, const glm::vec3& direction, float tnear,
                             float tfar) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
  float epsilon_ = 1e-4f;
};

}  // namespace omnishadow
