#include "renderer/view/caster_culling.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "renderer/view/caster_reach_grid.h"
#include "renderer/view/sphere_projection.h"

namespace omnishadow {

ViewFrustum::ViewFrustum(const glm::mat4& m) {
  const glm::vec4 r0(m[0][0], m[1][0], m[2][0], m[3][0]);
  const glm::vec4 r1(m[0][1], m[1][1], m[2][1], m[3][1]);
  const glm::vec4 r2(m[0][2], m[1][2], m[2][2], m[3][2]);
  const glm::vec4 r3(m[0][3], m[1][3], m[2][3], m[3][3]);
  // Reversed [0,1] depth: the near plane is z = w, the far plane z = 0.
  planes_ = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2};
  for (glm::vec4& p : planes_) p /= glm::length(glm::vec3(p));
}

bool ViewFrustum::touches(const glm::vec3& center, float radius) const {
  for (const glm::vec4& p : planes_)
    if (glm::dot(glm::vec3(p), center) + p.w < -radius) return false;
  return true;
}

TexelRect TexelRect::united(const TexelRect& other) const {
  if (other.empty()) return *this;
  if (empty()) return other;
  return {std::min(x0, other.x0), std::min(y0, other.y0), std::max(x1, other.x1),
          std::max(y1, other.y1)};
}

TexelRect TexelRect::intersected(const TexelRect& other) const {
  const TexelRect both{std::max(x0, other.x0), std::max(y0, other.y0), std::min(x1, other.x1),
                       std::min(y1, other.y1)};
  return both.empty() ? TexelRect{} : both;
}

TexelRect TexelRect::grown(int dx, int dy, int width, int height) const {
  if (empty()) return *this;
  return {std::max(x0 - dx, 0), std::max(y0 - dy, 0), std::min(x1 + dx, width),
          std::min(y1 + dy, height)};
}

TexelRect sphereTexelRect(const glm::mat4& viewProjection, const glm::vec3& center, float radius,
                          int resolution) {
  return ndcTexelRect(projectedSphereBox(viewProjection, center, radius), resolution, resolution);
}

TexelRect ndcTexelRect(const std::optional<NdcBounds>& ndc, int width, int height) {
  if (!ndc) return TexelRect::whole(width, height);
  const auto window = [](float v, int size) {
    return (v * 0.5f + 0.5f) * static_cast<float>(size);
  };
  const auto clamped = [](float v, int size) {
    return static_cast<int>(std::clamp(v, 0.0f, static_cast<float>(size)));
  };
  // A texel of margin on every side.
  const TexelRect rect{clamped(std::floor(window(ndc->low.x, width)) - 1.0f, width),
                       clamped(std::floor(window(ndc->low.y, height)) - 1.0f, height),
                       clamped(std::ceil(window(ndc->high.x, width)) + 1.0f, width),
                       clamped(std::ceil(window(ndc->high.y, height)) + 1.0f, height)};
  return rect.empty() ? TexelRect{} : rect;
}

unsigned uniteCasterTexels(const LightShadowPlan& plan, unsigned viewMask, const glm::vec3& center,
                           float radius, int resolution, std::vector<TexelRect>& texels,
                           const CasterBox* box) {
  for (int layer = 0; layer < plan.layerCount; ++layer) {
    if ((viewMask >> layer & 1u) == 0) continue;
    const auto l = static_cast<std::size_t>(layer);
    TexelRect rect = sphereTexelRect(plan.viewProjection[l], center, radius, resolution);
    if (box && !rect.empty())
      rect = rect.intersected(
          ndcTexelRect(projectedBox(plan.viewProjection[l], box->world, box->low, box->high),
                       resolution, resolution));
    if (rect.empty()) viewMask &= ~(1u << layer);
    texels[l] = texels[l].united(rect);
  }
  return viewMask;
}

ShadowCullingLight shadowCullingLight(const Light& light, const LightShadowPlan& plan, bool cube) {
  ShadowCullingLight culling;
  culling.type = light.type;
  culling.position = light.position;
  culling.direction = light.direction;
  culling.cullFace = light.shadow.cullFace;
  culling.viewProjections.assign(plan.viewProjection.begin(),
                                 plan.viewProjection.begin() + plan.layerCount);
  culling.near = plan.near;
  culling.far = plan.far;
  culling.tanHalfFov = cube ? 1.0f : plan.tanHalfFov;
  return culling;
}

unsigned casterViewMask(const std::vector<ViewFrustum>& views, const glm::vec3& center,
                        float radius) {
  unsigned mask = 0u;
  for (std::size_t v = 0; v < views.size(); ++v)
    if (views[v].touches(center, radius)) mask |= 1u << v;
  return mask;
}

bool seesOnlyFrontFaces(const ShadowCaster& caster, const ShadowCullingLight& light) {
  // Along any ray from a point outside a closed solid the first surface is a front face, so
  // its back faces cannot change a depth: they are skipped even with cullFace "none" (half the
  // triangles to set up and rasterize). "Outside" keeps a margin of the near plane's reach
  // (the frustum corner's distance at depth `near`), so that no front face is clipped away.
  // Masked casters are not solid where their texture cuts holes.
  if (!caster.closed || caster.masked) return false;
  if (light.type == LightType::Directional) return true;  // the depth range holds the scene
  const float t = light.tanHalfFov;
  const float nearReach = light.near * std::sqrt(1.0f + 2.0f * t * t);
  return glm::distance(light.position, caster.center) > caster.radius + nearReach;
}

CullBucket cullBucket(const ShadowCaster& caster, const ShadowCullingLight& light) {
  const bool userCull = light.cullFace != CullFace::None && !caster.doubleSided;
  if (!userCull && !(light.cullFace == CullFace::None && seesOnlyFrontFaces(caster, light)))
    return CullBucket::None;
  return caster.mirrored ? CullBucket::Cw : CullBucket::Ccw;
}

namespace {

// Whether every face of a point light's cube rejects the sphere, known from one bound: a
// face's far plane keeps its axis distance within far + r and its 90-degree side planes keep
// the other two coordinates within that distance + sqrt(2) r, so a sphere any face keeps has
// every coordinate within far + (1 + sqrt 2) r of the light (and a negative axis distance
// below near - r fails the near plane). 2.5 r and the relative margin stand above the float
// rounding of the planes, so the bound only skips spheres the planes reject: the masks are
// the planes' own. A light with a range reaches few of a large scene's casters.
bool outsideCubeReach(const ShadowCullingLight& light, const glm::vec3& center, float radius) {
  const float reach = light.far + 2.5f * radius + 1e-3f * (light.far + radius);
  const glm::vec3 d = glm::abs(center - light.position);
  return d.x > reach || d.y > reach || d.z > reach;
}

}  // namespace

bool shadowsNoReceiver(const MeshPlane& plane, const ShadowCullingLight& light,
                       const Bounds& receivers) {
  if (receivers.empty()) return false;
  // Receivers and the plane's own points come from float transforms: a tolerance of the
  // scene's size (and distance from the origin) keeps a box resting on the floor, its bottom a
  // rounding below it, on the floor's light side. Far below any shadow bias.
  const glm::vec3 reach = glm::max(glm::abs(receivers.min), glm::abs(receivers.max));
  const float tolerance =
      plane.thickness + 1e-5f * std::max(glm::length(receivers.max - receivers.min),
                                         std::max({reach.x, reach.y, reach.z}));
  // Which side the light is on: +1 where dot(normal, p) + offset > 0.
  float side = 0.0f;
  if (light.type == LightType::Directional) {
    const float towardsLight = -glm::dot(plane.normal, light.direction);
    if (std::abs(towardsLight) < 1e-3f) return false;  // grazing: the plane is nearly edge-on
    side = towardsLight > 0.0f ? 1.0f : -1.0f;
  } else {
    const float distance = glm::dot(plane.normal, light.position) + plane.offset;
    if (!(std::abs(distance) > tolerance)) return false;
    side = distance > 0.0f ? 1.0f : -1.0f;
  }
  // The box corner farthest on the far side.
  float farthest = -INFINITY;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? receivers.max.x : receivers.min.x,
                      (corner & 2) ? receivers.max.y : receivers.min.y,
                      (corner & 4) ? receivers.max.z : receivers.min.z);
    farthest = std::max(farthest, -side * (glm::dot(plane.normal, p) + plane.offset));
  }
  return farthest <= tolerance;
}

CasterCulling cullCasters(const std::vector<ShadowCaster>& casters, const ShadowCullingLight& light,
                          const Bounds& receivers, const CasterReachGrid* grid) {
  std::vector<ViewFrustum> views;
  views.reserve(light.viewProjections.size());
  for (const glm::mat4& viewProjection : light.viewProjections) views.emplace_back(viewProjection);
  const bool cube = light.type == LightType::Point && views.size() == 6 &&
                    light.tanHalfFov == 1.0f && light.far > 0.0f;
  CasterCulling culling;
  culling.viewMask.assign(casters.size(), 0u);
  culling.bucket.assign(casters.size(), CullBucket::None);
  const auto flat = [&](const ShadowCaster& caster) {
    return caster.plane && shadowsNoReceiver(*caster.plane, light, receivers);
  };
  const auto cull = [&](std::size_t c, bool leftOutFlat) {
    const ShadowCaster& caster = casters[c];
    // A depth map holds the nearest depth: the later copy draws the same one.
    if (leftOutFlat || caster.repeated ||
        (cube && outsideCubeReach(light, caster.center, caster.radius)))
      return;
    const unsigned mask = casterViewMask(views, caster.center, caster.radius);
    culling.viewMask[c] = mask;
    if (mask != 0u) culling.bucket[c] = cullBucket(caster, light);
  };
  if (!cube || grid == nullptr || grid->casterCount() != casters.size()) {
    for (std::size_t c = 0; c < casters.size(); ++c) {
      const bool leftOut = flat(casters[c]);
      culling.flatLeftOut += leftOut;
      cull(c, leftOut);
    }
    return culling;
  }
  // Every flat caster counts, reached or not; the others are tested only where the grid says
  // the bound may let them through (it rejects the rest).
  for (const std::uint32_t c : grid->flat()) culling.flatLeftOut += flat(casters[c]);
  std::vector<std::uint32_t> reached;
  grid->candidates(light.position, light.far, reached);
  for (const std::uint32_t c : reached) cull(c, flat(casters[c]));
  return culling;
}

}  // namespace omnishadow
