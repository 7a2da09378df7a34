#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "renderer/scene/bounds.h"
#include "renderer/scene/light.h"
#include "renderer/scene/mesh_topology.h"
#include "renderer/view/shadow_plan.h"
#include "renderer/view/sphere_projection.h"

namespace omnishadow {

// Which of a light's shadow views (cube faces, the spot map, cascades) each caster can touch,
// and how its triangles may be culled there. Plain data in and out: the shadow pass turns the
// answer into draws.

// The six clip-space planes of a view-projection with a [0,1] depth range, normalized.
class ViewFrustum {
 public:
  explicit ViewFrustum(const glm::mat4& viewProjection);
  // Conservative: true may still miss the view, false never does.
  bool touches(const glm::vec3& center, float radius) const;

 private:
  std::array<glm::vec4, 6> planes_;
};

// Texels [x0, x1) x [y0, y1) of a square view, in window coordinates (y up, as glScissor
// counts them); empty when x0 >= x1 or y0 >= y1.
struct TexelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
  // How many texels it holds (0 when empty).
  std::int64_t texels() const {
    return empty() ? 0 : static_cast<std::int64_t>(x1 - x0) * static_cast<std::int64_t>(y1 - y0);
  }
  // The smallest rectangle holding both (an empty one adds nothing).
  TexelRect united(const TexelRect& other) const;
  // The texels both hold (empty where they do not meet).
  TexelRect intersected(const TexelRect& other) const;
  // Grown by dx texels left and right and dy up and down, within a `resolution`-sided view (an
  // empty one stays empty).
  TexelRect grown(int dx, int dy, int resolution) const {
    return grown(dx, dy, resolution, resolution);
  }
  // The same within a `width` x `height` view.
  TexelRect grown(int dx, int dy, int width, int height) const;
  static TexelRect whole(int resolution) { return whole(resolution, resolution); }
  static TexelRect whole(int width, int height) { return {0, 0, width, height}; }
  bool operator==(const TexelRect& other) const = default;
};

// Conservative: the texels of a `resolution`-sided view that a sphere can cover, with a texel
// of margin; the whole view when the sphere reaches the plane of the view's eye (where a
// projection no longer bounds it), an empty rectangle when it lies outside the view.
TexelRect sphereTexelRect(const glm::mat4& viewProjection, const glm::vec3& center, float radius,
                          int resolution);
// The texels of a `width` x `height` view that `ndc` covers, with a texel of margin; the whole
// view without bounds (projectedBox(), projectedSphereBox()).
TexelRect ndcTexelRect(const std::optional<NdcBounds>& ndc, int width, int height);

// A caster's mesh box, which `world` places: the corners `low` and `high` in the mesh's space.
struct CasterBox {
  glm::mat4 world{1.0f};
  glm::vec3 low{0.0f}, high{0.0f};
};

// Unites into `texels` (one rectangle per layer of `plan`) what a caster's bounding sphere may
// cover in each layer of `viewMask`, at `resolution`, and with `box` only what its box may cover
// too (both bounds are conservative, so where they meet is); returns `viewMask` without the
// layers where it covers nothing. A flat or long caster's box is the tighter one where it lies
// oblique to the view; a small caster's sphere can be, where its box's corners lie outside it.
unsigned uniteCasterTexels(const LightShadowPlan& plan, unsigned viewMask, const glm::vec3& center,
                           float radius, int resolution, std::vector<TexelRect>& texels,
                           const CasterBox* box = nullptr);

// What culling needs to know of one caster (a draw of the scene).
struct ShadowCaster {
  glm::vec3 center{0.0f};  // world-space bounding sphere
  float radius = 0.0f;
  bool masked = false;             // alpha-tested or blended: its texture decides coverage
  bool closed = false;             // its mesh bounds a solid (isClosedSolid)
  bool doubleSided = false;        // its material's doubleSided
  bool mirrored = false;           // negative determinant: front faces are clockwise
  std::optional<MeshPlane> plane;  // world space, when its triangles are flat
  bool repeated = false;           // a later caster has the same triangles in the same place
};

// What culling needs to know of one light and its views.
struct ShadowCullingLight {
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // directional: where the light goes
  CullFace cullFace = CullFace::None;      // the light's shadow.cullFace
  std::vector<glm::mat4> viewProjections;
  float near = 0.0f;        // depth range start along the view axis
  float far = 0.0f;         // depth range end along the view axis (0: unknown)
  float tanHalfFov = 1.0f;  // of each view; cube faces are 90 degrees
};

// `cube`: the light's layers are cube faces (else planar: spot or cascades).
ShadowCullingLight shadowCullingLight(const Light& light, const LightShadowPlan& plan, bool cube);

// Culling states opaque casters are sorted into: both sides drawn, or back faces culled with
// counter-clockwise or clockwise front faces (mirrored transforms). The values order the draws.
enum class CullBucket { None = 0, Ccw, Cw };
inline constexpr int kCullBucketCount = 3;

// Bit v set: the caster's sphere touches view v.
unsigned casterViewMask(const std::vector<ViewFrustum>& views, const glm::vec3& center,
                        float radius);

// True when no back face of the caster can be nearest to the light, so that culling back faces
// changes no depth even where the user asked for no culling.
bool seesOnlyFrontFaces(const ShadowCaster& caster, const ShadowCullingLight& light);

CullBucket cullBucket(const ShadowCaster& caster, const ShadowCullingLight& light);

// True when a flat caster cannot come between the light and any point of `receivers`: the
// light lies clearly on one side of the caster's plane and no receiver on the other. Along a
// ray from the light to a receiver on the light's side (or on the plane itself, as the floor's
// own points are) the plane is met, if at all, only at the receiver, so the caster changes no
// comparison a receiver makes, except that it was the nearest surface there: a receiver's own
// texel, or a filter tap reaching past a floor or wall into nothing. Those compare lit
// without it, as the exact reference says (the seam where a wall meets the floor). Empty
// receivers cull nothing. A room's shell (floor, walls, ceiling) covers whole cube faces and
// is most of a shadow pass's texels.
bool shadowsNoReceiver(const MeshPlane& plane, const ShadowCullingLight& light,
                       const Bounds& receivers);

// Per caster, in caster order.
struct CasterCulling {
  std::vector<unsigned> viewMask;
  std::vector<CullBucket> bucket;  // None where viewMask is 0 (no draw asks)
  int flatLeftOut = 0;             // casters whose mask shadowsNoReceiver() emptied
};
class CasterReachGrid;

// `receivers`: where shadows can land (GpuGeometry::receiverBounds); empty when every caster
// must be drawn anyway (variance maps blur what the casters wrote into their neighbours).
// `grid` (of `casters`), when given, lets a point light test only the casters near it; the
// answer is the same either way.
CasterCulling cullCasters(const std::vector<ShadowCaster>& casters, const ShadowCullingLight& light,
                          const Bounds& receivers, const CasterReachGrid* grid = nullptr);

}  // namespace omnishadow
