#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "renderer/output/image_writer.h"
#include "renderer/scene/bounds.h"
#include "renderer/scene/light.h"
#include "renderer/verify/shadow_reference.h"
#include "renderer/view/camera.h"

namespace omnishadow {

// Compares the shadow term a renderer used (the visibility.<light> AOV) with exact shadow rays,
// pixel by pixel, and counts agreement, false shadow (acne, over-darkening) and false light
// (leaks, peter-panning), apart for points near a shadow boundary. CPU only. The rules are
// documented in the README ("omnishadow verify").

struct VerifySettings {
  float grazing = 0.05f;    // points with N.L (shading or geometric normal) below are skipped
  float edgeTexels = 3.0f;  // half-width of the shadow-edge band, in shadow-map texels
  int sourceSamples = 64;   // rays per point towards a light with shadow.radius > 0
  int threads = 0;          // 0 = one per core; results do not depend on it
  // > 0: also compare the AOVs' occlusion layer with rays (ambientVisibility()) that meet a
  // surface within 0.9 of this radius, the middle of the estimate's falloff, from each pixel's
  // triangle (AmbientOcclusionCounts).
  float occlusionRadius = 0.0f;
  int occlusionSamples = 64;
  // Indexed by materialId: materials with an occlusion texture, whose share the layer also
  // holds; their pixels are left out of that comparison.
  std::vector<bool> texturedMaterials;
};

// One light to check, with the far distance its point or spot shadow map was rendered with
// (effectiveShadowFar()).
struct LightToVerify {
  Light light;
  float shadowFar = 0.0f;
};

// What became of one pixel for one light. The first seven are skipped, the last three evaluated.
enum class Verdict : std::uint8_t {
  Background,       // no geometry
  OutOfRange,       // beyond the light's range
  OutsideCone,      // outside a spot light's outer cone
  FacingAway,       // N.L <= 0
  Grazing,          // N.L below VerifySettings::grazing
  BeyondShadowFar,  // beyond the shadow's far distance (directional: shadow.distance)
  Unlit,            // a KHR_materials_unlit surface: the lighting gives it no shadow term
  Agree,
  FalseShadow,  // the renderer shadowed it, the rays reach the light
  FalseLight,   // the renderer lit it, the rays are blocked
};

// Translucent shadows: a rendered transmittance.<light>.R/G/B agrees with the rays' when every
// channel is within this of theirs.
inline constexpr float kTransmittanceTolerance = 0.05f;

struct PointVerdict {
  Verdict verdict = Verdict::Background;
  bool edge = false;       // near a shadow boundary (evaluated points only)
  float reference = 1.0f;  // fraction of the light the rays reach (evaluated points only)
  // Lights with transmittance.<light> AOVs, interior points: the RGB comparison was made, and
  // every channel is within kTransmittanceTolerance.
  bool transmittanceChecked = false, transmittanceAgrees = false;
};

// Interior points of a light with transmittance AOVs whose RGB term was compared.
struct TransmittanceCounts {
  std::int64_t evaluated = 0, agree = 0;
  double agreementRate() const {
    return evaluated > 0 ? static_cast<double>(agree) / static_cast<double>(evaluated) : 0.0;
  }
};

struct SkipCounts {
  std::int64_t background = 0, outOfRange = 0, outsideCone = 0, facingAway = 0, grazing = 0,
               beyondShadowFar = 0, unlit = 0;
};

struct ClassCounts {
  std::int64_t evaluated = 0, agree = 0, falseShadow = 0, falseLight = 0;
  // Fractions of `evaluated`; 0 when nothing was evaluated.
  double agreementRate() const { return rate(agree); }
  double falseShadowRate() const { return rate(falseShadow); }
  double falseLightRate() const { return rate(falseLight); }

 private:
  double rate(std::int64_t n) const {
    return evaluated > 0 ? static_cast<double>(n) / static_cast<double>(evaluated) : 0.0;
  }
};

struct LightVerification {
  std::string name;
  LightType type = LightType::Point;
  bool shadowed = true;  // false: shadow.enabled is off; nothing was evaluated
  SkipCounts skipped;
  ClassCounts interior, edge;
  TransmittanceCounts transmittance;  // all zero without transmittance.<light> AOVs
  std::vector<PointVerdict> points;   // width x height, row 0 = top; empty when not shadowed
};

// The occlusion layer against the rays (VerifySettings::occlusionRadius): errors are the layer
// minus the rays' visible share.
struct AmbientOcclusionCounts {
  std::int64_t evaluated = 0;
  std::int64_t textured = 0;             // left out: an occlusion texture's share is in the layer
  std::int64_t darker = 0, lighter = 0;  // by more than kOcclusionErrorBound
  std::int64_t occluded = 0;             // the rays' share below kOccludedShare
  double sumError = 0.0, sumAbsoluteError = 0.0;
  double occludedAbsoluteError = 0.0;  // over the occluded points
  double occludedHidden = 0.0;         // sum of 1 - the rays' share there: the error of no estimate
  static double mean(double sum, std::int64_t n) {
    return n > 0 ? sum / static_cast<double>(n) : 0.0;
  }
};
inline constexpr float kOcclusionErrorBound = 0.25f;
inline constexpr float kOccludedShare = 0.9f;

struct ShadowVerification {
  int width = 0, height = 0;
  std::vector<LightVerification> lights;
  std::optional<AmbientOcclusionCounts> occlusion;  // VerifySettings::occlusionRadius > 0
};

// World size of one shadow-map texel at `point`, across the light's view: a point light's cube
// face texel 2 max(|d.x|, |d.y|, |d.z|) / resolution (d = point - light); a spot light's
// 2 |d| tan(outerConeAngle) / resolution; a directional light's map is taken to span the scene
// bounds across the light (the widest extent / resolution, conservative for cascades).
float shadowTexelWorldSize(const Light& light, const glm::vec3& point, const Bounds& sceneBounds);

// Half-width in world units of the band around a shadow boundary within which a point counts as
// an edge point: edgeTexels texels, plus the filter's own reach (pcf 1 texel, pcf-disk
// filterRadius x (1 + cameraDistance / shadowFar) texels, poisson and vsm filterRadius texels,
// pcss the light's radius in world units for point and spot lights).
float edgeBandWidth(const Light& light, const glm::vec3& point, float cameraDistance,
                    float shadowFar, const Bounds& sceneBounds, float edgeTexels);

// Checks every pixel of `aovs` (Frame::aovs: A, P.X/Y/Z, N.X/Y/Z, Z and visibility.<name> for
// every light in `lights`; with occlusionRadius, occlusion and materialId) rendered from
// `camera`. Throws RenderError when a channel is missing.
// A light whose AOVs have transmittance.<name>.R/G/B (translucent shadows) is also compared in
// RGB at interior points; its points are edge points where the rays' transmittance changes by
// more than kTransmittanceTolerance within the band, not where it is fractional.
ShadowVerification verifyShadows(const ShadowReference& reference, const Bounds& sceneBounds,
                                 const std::vector<LightToVerify>& lights, const FloatImage& aovs,
                                 const ViewCamera& camera, const VerifySettings& settings);

// The largest interior false-shadow or false-light rate over the shadowed lights.
double worstInteriorErrorRate(const LightVerification& light);

// RGB, 8 bits, width x height: the scene in grey (darker where the rays find shadow), red where
// the renderer shadows a lit point, blue where it lights a shadowed one; magenta when lights
// disagree both ways; errors at edge points are dimmer.
std::vector<std::uint8_t> errorImage(const ShadowVerification& verification, const FloatImage& aovs,
                                     const ViewCamera& camera);

}  // namespace omnishadow
