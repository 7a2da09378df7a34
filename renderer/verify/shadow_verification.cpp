#include "renderer/verify/shadow_verification.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include "renderer/core/errors.h"
#include "renderer/verify/ambient_occlusion_reference.h"

namespace omnishadow {
namespace {

// Where the channels of one light's pixels are in the AOV image.
struct AovLayout {
  int a = -1, p = -1, n = -1, z = -1;
  int occlusion = -1, materialId = -1;  // VerifySettings::occlusionRadius > 0
  std::vector<int> visibility;          // per light
  std::vector<int> transmittance;       // per light: transmittance.<name>.R, or -1
};

int requireChannel(const FloatImage& aovs, const std::string& name) {
  const int index = aovs.channelIndex(name);
  if (index < 0) throw RenderError("the AOVs have no channel " + name);
  return index;
}

AovLayout layoutOf(const FloatImage& aovs, const std::vector<LightToVerify>& lights,
                   bool occlusion) {
  AovLayout layout;
  layout.a = requireChannel(aovs, "A");
  layout.p = requireChannel(aovs, "P.X");
  layout.n = requireChannel(aovs, "N.X");
  layout.z = requireChannel(aovs, "Z");
  if (occlusion) {
    layout.occlusion = requireChannel(aovs, "occlusion");
    layout.materialId = requireChannel(aovs, "materialId");
  }
  if (aovs.channelIndex("P.Y") != layout.p + 1 || aovs.channelIndex("P.Z") != layout.p + 2 ||
      aovs.channelIndex("N.Y") != layout.n + 1 || aovs.channelIndex("N.Z") != layout.n + 2)
    throw RenderError("the AOVs' P and N channels are not in X, Y, Z order");
  for (const LightToVerify& l : lights) {
    layout.visibility.push_back(
        l.light.shadow.enabled ? requireChannel(aovs, "visibility." + l.light.name) : -1);
    const int r = aovs.channelIndex("transmittance." + l.light.name + ".R");
    if (r >= 0 && (aovs.channelIndex("transmittance." + l.light.name + ".G") != r + 1 ||
                   aovs.channelIndex("transmittance." + l.light.name + ".B") != r + 2))
      throw RenderError("the AOVs' transmittance." + l.light.name +
                        " channels are not in R, G, B order");
    layout.transmittance.push_back(r);
  }
  return layout;
}

// One visible surface point, as the AOVs and a camera ray describe it.
struct SurfacePoint {
  glm::vec3 position, normal, geometricNormal;  // both normals face the camera
  float cameraDistance;
  bool unlit = false;  // the camera ray meets a KHR_materials_unlit triangle there
};

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The camera ray through the point gives its triangle's geometric normal: the AOV normal is the
// shading normal, smoothed across corners and bent by normal maps, and the shadow map, like the
// reference rays, only knows the triangles. Also whether that triangle is unlit.
void findTriangle(const ShadowReference& reference, const glm::vec3& viewDirection,
                  SurfacePoint& s) {
  const float tolerance = 16.0f * reference.epsilon();
  const std::optional<SurfaceHit> hit = reference.intersect(s.position - viewDirection * tolerance,
                                                            viewDirection, 0.0f, 2.0f * tolerance);
  s.geometricNormal = s.normal;
  if (!hit) return;
  s.geometricNormal = glm::dot(hit->geometricNormal, viewDirection) > 0.0f ? -hit->geometricNormal
                                                                           : hit->geometricNormal;
  s.unlit = hit->unlit;
}

// Most points checked along each edge-band shift (README, "omnishadow verify").
constexpr int kMaxEdgeSteps = 8;

// Tells an evaluated point's class from a shadow ray fraction.
bool inShadow(float visibility) {
  return visibility < 0.5f;
}

bool within(const glm::vec3& a, const glm::vec3& b, float tolerance) {
  const glm::vec3 d = glm::abs(a - b);
  return d.x <= tolerance && d.y <= tolerance && d.z <= tolerance;
}

// `renderedRgb`: the transmittance.<light> AOVs at the point, null when the light has none.
PointVerdict judge(const ShadowReference& reference, const Bounds& bounds,
                   const LightToVerify& target, const SurfacePoint& s, float rendered,
                   const glm::vec3* renderedRgb, const VerifySettings& settings) {
  const Light& light = target.light;
  PointVerdict result;
  if (s.unlit) {
    result.verdict = Verdict::Unlit;
    return result;
  }
  glm::vec3 L;
  float distance = 0.0f;
  if (light.type == LightType::Directional) {
    L = glm::normalize(-light.direction);
  } else {
    const glm::vec3 toLight = light.position - s.position;
    distance = glm::length(toLight);
    L = distance > 0.0f ? toLight / distance : s.normal;
    if (light.range > 0.0f && distance >= light.range) {
      result.verdict = Verdict::OutOfRange;
      return result;
    }
    if (light.type == LightType::Spot &&
        glm::dot(glm::normalize(light.direction), -L) <= std::cos(light.outerConeAngle)) {
      result.verdict = Verdict::OutsideCone;
      return result;
    }
  }
  const float cosShading = glm::dot(s.normal, L);
  if (cosShading <= 0.0f) {
    result.verdict = Verdict::FacingAway;
    return result;
  }
  // The geometric test catches the terminator of smooth-shaded meshes, where the triangle
  // faces away from a light its shading normal still sees.
  if (cosShading < settings.grazing || glm::dot(s.geometricNormal, L) < settings.grazing) {
    result.verdict = Verdict::Grazing;
    return result;
  }
  const bool beyondFar =
      light.type == LightType::Directional
          ? light.shadow.distance > 0.0f && s.cameraDistance > light.shadow.distance
          : distance > target.shadowFar;
  if (beyondFar) {
    result.verdict = Verdict::BeyondShadowFar;
    return result;
  }

  glm::vec3 rgb(1.0f);
  float r;
  if (renderedRgb) {
    rgb = reference.transmittance(light, s.position, s.geometricNormal, settings.sourceSamples);
    r = (rgb.r + rgb.g + rgb.b) / 3.0f;  // as visibility() and the lighting pass average it
  } else {
    r = reference.visibility(light, s.position, s.geometricNormal, settings.sourceSamples);
  }
  const bool shadowed = inShadow(r);
  result.reference = r;
  // Behind translucent casters values near 0.5 are common: within the tolerance is agreement,
  // whichever side of 0.5 each falls.
  const bool renderedShadowed = renderedRgb && std::abs(rendered - r) <= kTransmittanceTolerance
                                    ? shadowed
                                    : inShadow(rendered);
  result.verdict = renderedShadowed == shadowed ? Verdict::Agree
                   : renderedShadowed           ? Verdict::FalseShadow
                                                : Verdict::FalseLight;

  // Behind translucent casters a fractional value is no boundary; the shifts below find those.
  result.edge = !renderedRgb && r > 0.0f && r < 1.0f;
  if (result.edge) return result;
  // Shift the point across the light's view by the band width: along the surface and across L,
  // and along the surface's slope away from L, stretched so that it moves the band width
  // across the light's view too (as a shadow-map texel is stretched on a tilted receiver).
  const float w = edgeBandWidth(light, s.position, s.cameraDistance, target.shadowFar, bounds,
                                settings.edgeTexels);
  const glm::vec3& Ng = s.geometricNormal;
  glm::vec3 across = glm::cross(Ng, L);
  if (glm::length(across) < 1e-6f) {
    const glm::vec3 helper = std::abs(Ng.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    across = glm::cross(Ng, helper);
  }
  across = glm::normalize(across);
  const glm::vec3 perpendicular = glm::normalize(glm::cross(L, across));
  // --grazing 0 lets N.L reach 0; the floor keeps the stretch finite.
  const glm::vec3 slope =
      perpendicular - L * (glm::dot(perpendicular, Ng) / std::max(glm::dot(L, Ng), 1e-3f));
  // Every texel or so along each shift, not only at its end: a lit gap or a thin shadow
  // narrower than the band would otherwise be stepped over, though the filter sees it. Not for
  // a light with a size: there such a gap gives fractional references, edges already, and each
  // point costs sourceSamples rays.
  const float texel = shadowTexelWorldSize(light, s.position, bounds);
  const int steps = texel > 0.0f && light.shadow.radius <= 0.0f
                        ? std::clamp(static_cast<int>(std::ceil(w / texel)), 1, kMaxEdgeSteps)
                        : 1;
  for (const glm::vec3& shift : {across, -across, slope, -slope}) {
    for (int step = 1; step <= steps && !result.edge; ++step) {
      const glm::vec3 at =
          s.position + shift * (w * static_cast<float>(step) / static_cast<float>(steps));
      if (renderedRgb) {
        const glm::vec3 shifted = reference.transmittance(light, at, Ng, settings.sourceSamples);
        result.edge = !within(shifted, rgb, kTransmittanceTolerance);
        continue;
      }
      const float shifted = reference.visibility(light, at, Ng, settings.sourceSamples);
      result.edge = inShadow(shifted) != shadowed || (shifted > 0.0f && shifted < 1.0f);
    }
    if (result.edge) break;
  }
  if (renderedRgb && !result.edge) {
    result.transmittanceChecked = true;
    result.transmittanceAgrees = within(*renderedRgb, rgb, kTransmittanceTolerance);
  }
  return result;
}

void count(const PointVerdict& point, LightVerification& light) {
  ClassCounts& group = point.edge ? light.edge : light.interior;
  switch (point.verdict) {
    case Verdict::Background:
      ++light.skipped.background;
      return;
    case Verdict::OutOfRange:
      ++light.skipped.outOfRange;
      return;
    case Verdict::OutsideCone:
      ++light.skipped.outsideCone;
      return;
    case Verdict::FacingAway:
      ++light.skipped.facingAway;
      return;
    case Verdict::Grazing:
      ++light.skipped.grazing;
      return;
    case Verdict::BeyondShadowFar:
      ++light.skipped.beyondShadowFar;
      return;
    case Verdict::Unlit:
      ++light.skipped.unlit;
      return;
    case Verdict::Agree:
      ++group.agree;
      break;
    case Verdict::FalseShadow:
      ++group.falseShadow;
      break;
    case Verdict::FalseLight:
      ++group.falseLight;
      break;
  }
  ++group.evaluated;
  if (point.transmittanceChecked) {
    ++light.transmittance.evaluated;
    if (point.transmittanceAgrees) ++light.transmittance.agree;
  }
}

std::uint8_t toByte(float v) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

float shadowTexelWorldSize(const Light& light, const glm::vec3& point, const Bounds& sceneBounds) {
  const float resolution = static_cast<float>(std::max(light.shadow.resolution, 1));
  if (light.type == LightType::Point) {
    const glm::vec3 d = glm::abs(point - light.position);
    return 2.0f * std::max({d.x, d.y, d.z}) / resolution;
  }
  if (light.type == LightType::Spot)
    return 2.0f * glm::length(point - light.position) * std::tan(light.outerConeAngle) / resolution;
  if (sceneBounds.empty()) return 0.0f;
  const glm::vec3 L = glm::normalize(light.direction);
  const glm::vec3 helper = std::abs(L.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 right = glm::normalize(glm::cross(helper, L));
  const glm::vec3 up = glm::cross(L, right);
  float minRight = 1e30f, maxRight = -1e30f, minUp = 1e30f, maxUp = -1e30f;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 c{(corner & 1) ? sceneBounds.max.x : sceneBounds.min.x,
                      (corner & 2) ? sceneBounds.max.y : sceneBounds.min.y,
                      (corner & 4) ? sceneBounds.max.z : sceneBounds.min.z};
    minRight = std::min(minRight, glm::dot(c, right));
    maxRight = std::max(maxRight, glm::dot(c, right));
    minUp = std::min(minUp, glm::dot(c, up));
    maxUp = std::max(maxUp, glm::dot(c, up));
  }
  return std::max(maxRight - minRight, maxUp - minUp) / resolution;
}

float edgeBandWidth(const Light& light, const glm::vec3& point, float cameraDistance,
                    float shadowFar, const Bounds& sceneBounds, float edgeTexels) {
  const ShadowSettings& shadow = light.shadow;
  float filterTexels = 0.0f;
  float filterWorld = 0.0f;
  switch (shadow.filter) {
    case ShadowFilter::Hard:
      break;
    case ShadowFilter::Pcf:
      filterTexels = 1.0f;
      break;  // the 2x2 footprint
    case ShadowFilter::PcfDisk:
      filterTexels =
          shadow.filterRadius * (1.0f + (shadowFar > 0.0f ? cameraDistance / shadowFar : 1.0f));
      break;
    case ShadowFilter::Poisson:
    case ShadowFilter::Vsm:
      filterTexels = shadow.filterRadius;
      break;
    case ShadowFilter::Pcss:
      // The true penumbra is caught by the fractional reference; this covers PCSS's estimate
      // of it, which is at most the light's size while the receiver is no farther behind the
      // blocker than the blocker is from the light.
      if (light.type != LightType::Directional) filterWorld = shadow.radius;
      break;
  }
  return shadowTexelWorldSize(light, point, sceneBounds) * (edgeTexels + filterTexels) +
         filterWorld;
}

ShadowVerification verifyShadows(const ShadowReference& reference, const Bounds& sceneBounds,
                                 const std::vector<LightToVerify>& lights, const FloatImage& aovs,
                                 const ViewCamera& camera, const VerifySettings& settings) {
  const bool occlusion = settings.occlusionRadius > 0.0f;
  const AovLayout layout = layoutOf(aovs, lights, occlusion);
  // Each pixel's estimate and the rays' share (NaN: not compared), summed in order after.
  std::vector<glm::vec2> occlusionPairs(
      occlusion ? static_cast<std::size_t>(aovs.width) * aovs.height : 0,
      glm::vec2(std::numeric_limits<float>::quiet_NaN()));
  std::atomic<std::int64_t> textured{0};
  ShadowVerification result;
  result.width = aovs.width;
  result.height = aovs.height;
  const std::size_t pixels = static_cast<std::size_t>(aovs.width) * aovs.height;
  for (const LightToVerify& l : lights) {
    LightVerification light;
    light.name = l.light.name;
    light.type = l.light.type;
    light.shadowed = l.light.shadow.enabled;
    if (light.shadowed) light.points.resize(pixels);
    result.lights.push_back(std::move(light));
  }

  const glm::mat4 cameraToWorld = glm::inverse(camera.view);
  const glm::vec3 forward = -glm::normalize(glm::vec3(cameraToWorld[2]));
  // Rows are handed out one at a time; each pixel's verdict goes to its own slot, so the result
  // is the same for any number of threads.
  std::atomic<int> nextRow{0};
  auto work = [&] {
    for (int y = nextRow++; y < aovs.height; y = nextRow++) {
      for (int x = 0; x < aovs.width; ++x) {
        const std::size_t index = static_cast<std::size_t>(y) * aovs.width + x;
        SurfacePoint s;
        s.position = {aovs.at(x, y, layout.p), aovs.at(x, y, layout.p + 1),
                      aovs.at(x, y, layout.p + 2)};
        s.normal = {aovs.at(x, y, layout.n), aovs.at(x, y, layout.n + 1),
                    aovs.at(x, y, layout.n + 2)};
        s.cameraDistance = aovs.at(x, y, layout.z);
        const float normalLength = glm::length(s.normal);
        if (!(aovs.at(x, y, layout.a) > 0.0f) || !finite(s.position) || !finite(s.normal) ||
            !(normalLength > 0.0f) || !std::isfinite(s.cameraDistance))
          continue;  // background: the verdicts stay Verdict::Background
        s.normal /= normalLength;
        glm::vec3 view = camera.orthographic ? forward : s.position - camera.eye;
        view = glm::length(view) > 0.0f ? glm::normalize(view) : forward;
        findTriangle(reference, view, s);
        if (occlusion) {
          const float material = aovs.at(x, y, layout.materialId);
          const auto m = static_cast<std::size_t>(std::max(material, 0.0f));
          if (m < settings.texturedMaterials.size() && settings.texturedMaterials[m])
            ++textured;
          else
            occlusionPairs[index] = {
                aovs.at(x, y, layout.occlusion),
                ambientVisibility(reference, s.position, s.geometricNormal,
                                  0.9f * settings.occlusionRadius, settings.occlusionSamples)};
        }
        for (std::size_t i = 0; i < lights.size(); ++i) {
          if (!lights[i].light.shadow.enabled) continue;
          const int t = layout.transmittance[i];
          const glm::vec3 rgb =
              t >= 0 ? glm::vec3(aovs.at(x, y, t), aovs.at(x, y, t + 1), aovs.at(x, y, t + 2))
                     : glm::vec3(1.0f);
          result.lights[i].points[index] =
              judge(reference, sceneBounds, lights[i], s, aovs.at(x, y, layout.visibility[i]),
                    t >= 0 ? &rgb : nullptr, settings);
        }
      }
    }
  };
  int threads = settings.threads > 0 ? settings.threads
                                     : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, std::max(aovs.height, 1));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();

  for (LightVerification& light : result.lights)
    for (const PointVerdict& point : light.points) count(point, light);
  if (occlusion) {
    AmbientOcclusionCounts counts;
    counts.textured = textured;
    for (const glm::vec2& pair : occlusionPairs) {
      if (std::isnan(pair.x) || std::isnan(pair.y)) continue;
      const double error = static_cast<double>(pair.x) - pair.y;
      ++counts.evaluated;
      counts.sumError += error;
      counts.sumAbsoluteError += std::abs(error);
      counts.darker += error < -kOcclusionErrorBound;
      counts.lighter += error > kOcclusionErrorBound;
      if (pair.y < kOccludedShare) {
        ++counts.occluded;
        counts.occludedAbsoluteError += std::abs(error);
        counts.occludedHidden += 1.0 - pair.y;
      }
    }
    result.occlusion = counts;
  }
  return result;
}

double worstInteriorErrorRate(const LightVerification& light) {
  if (!light.shadowed) return 0.0;
  return std::max(light.interior.falseShadowRate(), light.interior.falseLightRate());
}

std::vector<std::uint8_t> errorImage(const ShadowVerification& verification, const FloatImage& aovs,
                                     const ViewCamera& camera) {
  const int p = aovs.channelIndex("P.X"), n = aovs.channelIndex("N.X"), a = aovs.channelIndex("A");
  const glm::vec3 forward = -glm::normalize(glm::vec3(glm::inverse(camera.view)[2]));
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(verification.width) * verification.height *
                                3);
  for (int y = 0; y < verification.height; ++y) {
    for (int x = 0; x < verification.width; ++x) {
      const std::size_t index = static_cast<std::size_t>(y) * verification.width + x;
      glm::vec3 color(0.0f);
      if (a >= 0 && p >= 0 && n >= 0 && aovs.at(x, y, a) > 0.0f) {
        const glm::vec3 position{aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)};
        const glm::vec3 normal{aovs.at(x, y, n), aovs.at(x, y, n + 1), aovs.at(x, y, n + 2)};
        glm::vec3 view = camera.orthographic ? forward : position - camera.eye;
        const float facing = glm::length(view) > 0.0f && glm::length(normal) > 0.0f
                                 ? std::abs(glm::dot(glm::normalize(view), glm::normalize(normal)))
                                 : 1.0f;
        // Mean reference visibility over the lights that evaluated this point darkens the grey,
        // so the true shadows show under the errors.
        float lit = 0.0f;
        int evaluated = 0;
        bool falseShadow = false, falseLight = false, interiorError = false;
        for (const LightVerification& light : verification.lights) {
          if (light.points.empty()) continue;
          const PointVerdict& v = light.points[index];
          if (v.verdict < Verdict::Agree) continue;
          lit += v.reference;
          ++evaluated;
          if (v.verdict == Verdict::FalseShadow) falseShadow = true;
          if (v.verdict == Verdict::FalseLight) falseLight = true;
          if (v.verdict != Verdict::Agree && !v.edge) interiorError = true;
        }
        const float shade =
            evaluated > 0 ? 0.55f + 0.45f * lit / static_cast<float>(evaluated) : 0.55f;
        color = glm::vec3((0.15f + 0.45f * facing) * shade);
        if (falseShadow || falseLight) {
          color = falseShadow && falseLight ? glm::vec3(1.0f, 0.1f, 1.0f)
                  : falseShadow             ? glm::vec3(1.0f, 0.1f, 0.05f)
                                            : glm::vec3(0.1f, 0.55f, 1.0f);
          if (!interiorError) color *= 0.5f;
        }
      }
      for (int c = 0; c < 3; ++c) rgb[index * 3 + c] = toByte(color[c]);
    }
  }
  return rgb;
}

}  // namespace omnishadow
