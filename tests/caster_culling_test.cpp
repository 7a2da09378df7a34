// Which shadow views a caster reaches, how it may be culled, and how its draws are batched.
#include "renderer/view/caster_culling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <utility>
#include <vector>

#include "renderer/view/cube_faces.h"
#include "renderer/view/shadow_draws.h"
#include "renderer/view/shadow_views.h"
#include "renderer/view/sphere_projection.h"
#include "tests/support/cube_culling_light.h"

namespace caster_culling_test {

using namespace omnishadow;

namespace {

constexpr unsigned kAllFaces = 0x3fu;

unsigned faceBit(CubeFace face) {
  return 1u << static_cast<int>(face);
}

// A point light at `position` with near 0.1 and far 100, like the shadow plan makes it.
ShadowCullingLight pointLight(const glm::vec3& position, CullFace cullFace = CullFace::None,
                              float near = 0.1f, float far = 100.0f) {
  return test::cubeCullingLight(position, cullFace, near, far);
}

// A spot light at the origin looking down -z, outer cone 30 degrees, near 0.5, far 20.
ShadowCullingLight spotLight() {
  Light spot;
  spot.type = LightType::Spot;
  spot.direction = {0.0f, 0.0f, -1.0f};
  spot.outerConeAngle = 0.5235988f;
  const SpotShadowFrame frame = spotShadowFrame(spot, 0.5f, 20.0f, 512);
  ShadowCullingLight light;
  light.type = LightType::Spot;
  light.position = spot.position;
  light.near = 0.5f;
  light.tanHalfFov = frame.tanHalfFov;
  light.viewProjections = {frame.viewProjection};
  return light;
}

unsigned maskOf(const ShadowCullingLight& light, const glm::vec3& center, float radius) {
  ShadowCaster caster;
  caster.center = center;
  caster.radius = radius;
  return cullCasters({caster}, light, Bounds{}).viewMask[0];
}

}  // namespace

// cullCasters skips the planes of a point light's faces for spheres beyond a bound of its far
// distance; the masks must be the planes' own, for spheres on every side of that bound.
TEST(CasterCulling, CubeReachBoundKeepsThePlanesMasks) {
  std::uint32_t state = 12345u;
  const auto uniform = [&state](float lo, float hi) {
    state = state * 1664525u + 1013904223u;
    return lo + (hi - lo) * static_cast<float>(state >> 8) / 16777216.0f;
  };
  int kept = 0, skipped = 0;
  for (int l = 0; l < 40; ++l) {
    const glm::vec3 at(uniform(-50, 50), uniform(-50, 50), uniform(-50, 50));
    const float far = uniform(0.5f, 30.0f);
    const ShadowCullingLight light = pointLight(at, CullFace::None, far * 0.01f, far);
    std::vector<ViewFrustum> views;
    for (const glm::mat4& m : light.viewProjections) views.emplace_back(m);
    std::vector<ShadowCaster> casters;
    for (int c = 0; c < 2000; ++c) {
      ShadowCaster caster;
      caster.radius = uniform(0.0f, 1.0f) < 0.2f ? uniform(0.0f, 0.01f) : uniform(0.0f, far);
      // Around the bound: up to far + 3 r from the light along each axis.
      const float extent = far + 3.0f * caster.radius;
      caster.center = at + glm::vec3(uniform(-extent, extent), uniform(-extent, extent),
                                     uniform(-extent, extent));
      casters.push_back(caster);
    }
    const CasterCulling culling = cullCasters(casters, light, Bounds{});
    for (std::size_t c = 0; c < casters.size(); ++c) {
      const unsigned planes = casterViewMask(views, casters[c].center, casters[c].radius);
      ASSERT_EQ(culling.viewMask[c], planes) << "light " << l << " caster " << c;
      (planes != 0 ? kept : skipped)++;
    }
  }
  // Both sides of the bound were tried.
  EXPECT_GT(kept, 10000);
  EXPECT_GT(skipped, 10000);
}

TEST(CasterCulling, SphereInsideOneCubeFaceTouchesThatFaceOnly) {
  const glm::vec3 at(2.0f, -1.0f, 3.0f);
  const ShadowCullingLight light = pointLight(at);
  EXPECT_EQ(maskOf(light, at + glm::vec3(5, 0, 0), 0.5f), faceBit(CubeFace::PosX));
  EXPECT_EQ(maskOf(light, at + glm::vec3(-5, 0, 0), 0.5f), faceBit(CubeFace::NegX));
  EXPECT_EQ(maskOf(light, at + glm::vec3(0, 5, 0), 0.5f), faceBit(CubeFace::PosY));
  EXPECT_EQ(maskOf(light, at + glm::vec3(0, -5, 0), 0.5f), faceBit(CubeFace::NegY));
  EXPECT_EQ(maskOf(light, at + glm::vec3(0, 0, 5), 0.5f), faceBit(CubeFace::PosZ));
  EXPECT_EQ(maskOf(light, at + glm::vec3(0, 0, -5), 0.5f), faceBit(CubeFace::NegZ));
}

TEST(CasterCulling, SphereStraddlingAFaceBoundaryTouchesBothFaces) {
  const ShadowCullingLight light = pointLight(glm::vec3(0.0f));
  // On the plane x = z between +x and +z.
  EXPECT_EQ(maskOf(light, {5, 0, 5}, 0.5f), faceBit(CubeFace::PosX) | faceBit(CubeFace::PosZ));
  // On the corner direction (1, 1, 1): three faces.
  EXPECT_EQ(maskOf(light, {5, 5, 5}, 0.5f),
            faceBit(CubeFace::PosX) | faceBit(CubeFace::PosY) | faceBit(CubeFace::PosZ));
}

TEST(CasterCulling, SphereContainingTheLightTouchesAllSixFaces) {
  const ShadowCullingLight light = pointLight(glm::vec3(1.0f, 2.0f, 3.0f));
  EXPECT_EQ(maskOf(light, {1.5f, 2.0f, 3.0f}, 2.0f), kAllFaces);
}

// Of two casters with the same triangles in the same place, only the later is drawn: a depth
// map holds the nearest depth once.
TEST(CasterCulling, ARepeatedCasterIsLeftToItsLaterCopy) {
  const ShadowCullingLight light = pointLight(glm::vec3(0.0f));
  ShadowCaster caster;
  caster.center = {5.0f, 0.0f, 0.0f};
  caster.radius = 0.5f;
  ShadowCaster repeated = caster;
  repeated.repeated = true;
  const CasterCulling culling = cullCasters({repeated, caster}, light, Bounds{});
  EXPECT_EQ(culling.viewMask[0], 0u);
  EXPECT_EQ(culling.viewMask[1], faceBit(CubeFace::PosX));
}

TEST(CasterCulling, SphereOutsideTheDepthRangeTouchesNoFace) {
  const ShadowCullingLight light = pointLight(glm::vec3(0.0f));
  EXPECT_EQ(maskOf(light, {150, 0, 0}, 1.0f), 0u);  // beyond far = 100
  EXPECT_EQ(maskOf(light, {0, 0, -101}, 0.5f), 0u);
  // Tiny and closer than near = 0.1, off the light itself: between all near planes.
  EXPECT_EQ(maskOf(light, {0.03f, 0.02f, 0.0f}, 0.001f), 0u);
  // Just reaching across far: still drawn.
  EXPECT_EQ(maskOf(light, {100.5f, 0, 0}, 1.0f), faceBit(CubeFace::PosX));
}

TEST(CasterCulling, SphereTexelRectBoundsEveryPointOfTheSphereItProjects) {
  // A sphere straight ahead of +X at distance 5, radius 0.5: its box's near corners, 4.5 ahead
  // and 0.5 aside, are 0.5 / 4.5 of the half-width (57 of 512 texels) off the center, plus a
  // texel of margin.
  const glm::vec3 at(2.0f, -1.0f, 3.0f);
  const glm::mat4 viewProjection = pointLight(at).viewProjections[0];
  const int n = 1024;
  const TexelRect rect = sphereTexelRect(viewProjection, at + glm::vec3(5, 0, 0), 0.5f, n);
  EXPECT_NEAR(rect.x0, 512 - 57 - 1, 1);
  EXPECT_NEAR(rect.x1, 512 + 57 + 1, 1);
  EXPECT_NEAR(rect.y0, 512 - 57 - 1, 1);
  EXPECT_NEAR(rect.y1, 512 + 57 + 1, 1);
  // Every point of an off-center sphere lands inside its rectangle.
  const glm::vec3 center = at + glm::vec3(4.0f, 1.5f, -2.0f);
  const TexelRect off = sphereTexelRect(viewProjection, center, 0.7f, n);
  for (int i = 0; i < 2000; ++i) {
    const float u = static_cast<float>(i) * 0.61803398875f, v = static_cast<float>(i) / 2000.0f;
    const float z = 2.0f * v - 1.0f, r = std::sqrt(1.0f - z * z);
    const glm::vec3 p =
        center + 0.7f * glm::vec3(r * std::cos(6.2831853f * u), r * std::sin(6.2831853f * u), z);
    const glm::vec4 clip = viewProjection * glm::vec4(p, 1.0f);
    const glm::vec2 window = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * static_cast<float>(n);
    ASSERT_GE(window.x, static_cast<float>(off.x0));
    ASSERT_LT(window.x, static_cast<float>(off.x1));
    ASSERT_GE(window.y, static_cast<float>(off.y0));
    ASSERT_LT(window.y, static_cast<float>(off.y1));
  }
  // Reaching behind the light's eye plane: the whole face. Beside the face: nothing.
  const TexelRect around = sphereTexelRect(viewProjection, at + glm::vec3(0.2f, 0, 0), 0.5f, n);
  EXPECT_EQ(around.x0, 0);
  EXPECT_EQ(around.y0, 0);
  EXPECT_EQ(around.x1, n);
  EXPECT_EQ(around.y1, n);
  EXPECT_TRUE(sphereTexelRect(viewProjection, at + glm::vec3(5, 20, 0), 0.5f, n).empty());
}

// What a camera's frame may show of a placed box (the lighting pass clears no more than that).
TEST(CasterCulling, NdcTexelRectOfABoxBoundsEveryPointOfTheBoxOnAWideFrame) {
  const glm::mat4 viewProjection =
      glm::perspective(glm::radians(50.0f), 1280.0f / 720.0f, 0.1f, 100.0f) *
      glm::lookAt(glm::vec3(0.3f, 1.2f, 4.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0));
  // Turned, stretched and moved to the right of the view.
  const glm::mat4 model =
      glm::translate(glm::mat4(1.0f), glm::vec3(1.1f, 0.2f, -0.5f)) *
      glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 0.5f))) *
      glm::scale(glm::mat4(1.0f), glm::vec3(0.5f, 0.2f, 0.9f));
  const glm::vec3 low(-1.0f, -0.5f, -0.25f), high(0.5f, 1.0f, 0.75f);
  const TexelRect rect = ndcTexelRect(projectedBox(viewProjection, model, low, high), 1280, 720);
  ASSERT_FALSE(rect.empty());
  EXPECT_GT(rect.x0, 640);  // right of the centre, and well inside the frame
  EXPECT_LT((rect.x1 - rect.x0) * (rect.y1 - rect.y0), 1280 * 720 / 4);
  int onEdge = 0;
  for (int i = 0; i < 4096; ++i) {
    const glm::vec3 t(static_cast<float>(i % 16) / 15.0f, static_cast<float>(i / 16 % 16) / 15.0f,
                      static_cast<float>(i / 256) / 15.0f);
    const glm::vec4 clip = viewProjection * model * glm::vec4(low + t * (high - low), 1.0f);
    const glm::vec2 window = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * glm::vec2(1280, 720);
    ASSERT_GE(window.x, static_cast<float>(rect.x0) + 1.0f);  // a pixel of margin
    ASSERT_LE(window.x, static_cast<float>(rect.x1) - 1.0f);
    ASSERT_GE(window.y, static_cast<float>(rect.y0) + 1.0f);
    ASSERT_LE(window.y, static_cast<float>(rect.y1) - 1.0f);
    onEdge += window.x < static_cast<float>(rect.x0) + 3.0f;
  }
  EXPECT_GT(onEdge, 0);  // tight: some corner is within two pixels of the margin
  // Reaching behind the eye: the whole frame. Beside the frame: nothing.
  const glm::mat4 atEye = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 1.2f, 4.0f));
  EXPECT_EQ(ndcTexelRect(projectedBox(viewProjection, atEye, low, high), 1280, 720),
            (TexelRect{0, 0, 1280, 720}));
  const glm::mat4 aside = glm::translate(glm::mat4(1.0f), glm::vec3(30.0f, 0.0f, 0.0f));
  EXPECT_TRUE(ndcTexelRect(projectedBox(viewProjection, aside, low, high), 1280, 720).empty());
}

// A caster's box as well as its sphere (the translucent casters' reach): a flat pane tilted
// across a cube face, whose sphere is as wide as the pane, covers a narrower strip of the face
// than its sphere does. The rectangle is where the two bounds meet; every point of the pane lies
// in it; a layer the sphere reaches and the box does not is left out.
TEST(CasterCulling, UnitedCasterTexelsOfABoxAndItsSphereAreWhereBothBoundsMeet) {
  const glm::vec3 at(0.0f, 0.0f, 0.0f);
  const ShadowCullingLight light = pointLight(at);
  LightShadowPlan plan;
  plan.layerCount = 6;
  for (int face = 0; face < 6; ++face)
    plan.viewProjection[static_cast<std::size_t>(face)] =
        light.viewProjections[static_cast<std::size_t>(face)];
  std::vector<ViewFrustum> views;
  for (int face = 0; face < 6; ++face)
    views.emplace_back(plan.viewProjection[static_cast<std::size_t>(face)]);
  const int n = 1024;
  // A 2 x 2 pane (z = 0 in its own space) 4 ahead along +X, turned 80 degrees about y: nearly
  // edge-on to the +X face.
  const glm::mat4 world = glm::translate(glm::mat4(1.0f), glm::vec3(4.0f, 0.0f, 0.0f)) *
                          glm::rotate(glm::mat4(1.0f), glm::radians(80.0f), glm::vec3(0, 1, 0));
  const CasterBox box{world, glm::vec3(-1.0f, -1.0f, 0.0f), glm::vec3(1.0f, 1.0f, 0.0f)};
  const glm::vec3 center = glm::vec3(world * glm::vec4(0, 0, 0, 1));
  const float radius = std::sqrt(2.0f);
  const auto posX = static_cast<std::size_t>(CubeFace::PosX);
  std::vector<TexelRect> spheres(6), both(6);
  // As translucentReach() asks: the faces whose frusta the sphere touches.
  const unsigned touched = casterViewMask(views, center, radius);
  const unsigned bySphere = uniteCasterTexels(plan, touched, center, radius, n, spheres);
  const unsigned byBoth = uniteCasterTexels(plan, touched, center, radius, n, both, &box);
  EXPECT_EQ(bySphere, faceBit(CubeFace::PosX));
  EXPECT_EQ(byBoth, faceBit(CubeFace::PosX));
  const TexelRect boxRect =
      ndcTexelRect(projectedBox(plan.viewProjection[posX], world, box.low, box.high), n, n);
  EXPECT_EQ(both[posX], spheres[posX].intersected(boxRect));
  EXPECT_LT(both[posX].x1 - both[posX].x0, (spheres[posX].x1 - spheres[posX].x0) / 2);
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      const glm::vec4 p = world * glm::vec4(i / 20.0f - 1.0f, j / 20.0f - 1.0f, 0.0f, 1.0f);
      const glm::vec4 clip = plan.viewProjection[posX] * p;
      const glm::vec2 window = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * static_cast<float>(n);
      ASSERT_GE(window.x, static_cast<float>(both[posX].x0));
      ASSERT_LT(window.x, static_cast<float>(both[posX].x1));
      ASSERT_GE(window.y, static_cast<float>(both[posX].y0));
      ASSERT_LT(window.y, static_cast<float>(both[posX].y1));
    }
  // A long thin box along +X whose sphere reaches into the +Y face: only its box's face stays.
  const glm::mat4 rod = glm::translate(glm::mat4(1.0f), glm::vec3(6.0f, 2.4f, 0.0f));
  const CasterBox rodBox{rod, glm::vec3(-3.0f, -0.05f, -0.05f), glm::vec3(3.0f, 0.05f, 0.05f)};
  const glm::vec3 rodCenter(6.0f, 2.4f, 0.0f);
  std::vector<TexelRect> rodSphere(6), rodBoth(6);
  const unsigned rodTouched = casterViewMask(views, rodCenter, 3.0f);
  const unsigned rodBySphere = uniteCasterTexels(plan, rodTouched, rodCenter, 3.0f, n, rodSphere);
  const unsigned rodByBoth =
      uniteCasterTexels(plan, rodTouched, rodCenter, 3.0f, n, rodBoth, &rodBox);
  EXPECT_NE(rodBySphere & faceBit(CubeFace::PosY), 0u);
  EXPECT_EQ(rodByBoth, faceBit(CubeFace::PosX));
  EXPECT_TRUE(rodBoth[static_cast<std::size_t>(CubeFace::PosY)].empty());
}

TEST(CasterCulling, TexelRectsIntersectToWhereTheyMeetAndApartToNothing) {
  const TexelRect a{10, 20, 30, 40}, b{25, 5, 50, 22};
  EXPECT_EQ(a.intersected(b), (TexelRect{25, 20, 30, 22}));
  EXPECT_EQ(b.intersected(a), (TexelRect{25, 20, 30, 22}));
  EXPECT_TRUE(a.intersected(TexelRect{30, 20, 40, 40}).empty());  // touching edges only
  EXPECT_TRUE(a.intersected(TexelRect{}).empty());
  EXPECT_EQ(a.intersected(TexelRect::whole(64)), a);
}

TEST(CasterCulling, TexelRectsUniteToTheirBoundsAndEmptyOnesAddNothing) {
  const TexelRect a{10, 20, 30, 40}, b{25, 5, 50, 22};
  const TexelRect both = a.united(b);
  EXPECT_EQ(both.x0, 10);
  EXPECT_EQ(both.y0, 5);
  EXPECT_EQ(both.x1, 50);
  EXPECT_EQ(both.y1, 40);
  const TexelRect alone = a.united(TexelRect{});
  EXPECT_EQ(alone.x0, a.x0);
  EXPECT_EQ(alone.x1, a.x1);
  EXPECT_EQ(TexelRect{}.united(b).y1, b.y1);
  EXPECT_TRUE(TexelRect{}.empty());
  EXPECT_FALSE(TexelRect::whole(4).empty());
}

TEST(CasterCulling, SpotFrustum) {
  const ShadowCullingLight light = spotLight();
  EXPECT_EQ(maskOf(light, {0, 0, -5}, 0.5f), 1u);     // on the axis
  EXPECT_EQ(maskOf(light, {0, 0, 5}, 0.5f), 0u);      // behind the light
  EXPECT_EQ(maskOf(light, {0, 0, -0.2f}, 0.1f), 0u);  // before the near plane
  EXPECT_EQ(maskOf(light, {0, 0, -25}, 1.0f), 0u);    // beyond far
  EXPECT_EQ(maskOf(light, {10, 0, -5}, 0.5f), 0u);    // far outside the cone
  EXPECT_EQ(maskOf(light, {3.2f, 0, -5}, 0.5f), 1u);  // reaching in from the cone's side
  EXPECT_EQ(maskOf(light, {0, 0, 2.0f}, 2.7f), 1u);   // from behind, across the near plane
}

TEST(CasterCulling, PlanarViewsAreTestedEachOnTheirOwn) {
  // Two cascades: orthographic boxes side by side along x.
  ShadowCullingLight light;
  light.type = LightType::Directional;
  const glm::mat4 flip(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 1, 1);  // z -> 1 - z
  const auto box = [&](float left, float right) {
    // x in [left, right], y in [-1, 1], depth along -z from 0 to 10, reversed.
    glm::mat4 m(1.0f);
    m[0][0] = 2.0f / (right - left);
    m[3][0] = -(right + left) / (right - left);
    m[2][2] = -0.1f;
    return flip * m;
  };
  light.viewProjections = {box(-2, 0), box(0, 2)};
  EXPECT_EQ(maskOf(light, {-1, 0, -5}, 0.2f), 1u);
  EXPECT_EQ(maskOf(light, {1, 0, -5}, 0.2f), 2u);
  EXPECT_EQ(maskOf(light, {0, 0, -5}, 0.2f), 3u);
  EXPECT_EQ(maskOf(light, {5, 0, -5}, 0.2f), 0u);
  EXPECT_EQ(maskOf(light, {1, 0, -15}, 0.2f), 0u);
}

TEST(CasterCulling, BucketsFollowTheLightsCullFaceAndTheMaterial) {
  ShadowCaster open;
  open.center = {5, 0, 0};
  open.radius = 1.0f;
  EXPECT_EQ(cullBucket(open, pointLight({0, 0, 0}, CullFace::None)), CullBucket::None);
  EXPECT_EQ(cullBucket(open, pointLight({0, 0, 0}, CullFace::Back)), CullBucket::Ccw);
  EXPECT_EQ(cullBucket(open, pointLight({0, 0, 0}, CullFace::Front)), CullBucket::Ccw);
  ShadowCaster mirrored = open;
  mirrored.mirrored = true;
  EXPECT_EQ(cullBucket(mirrored, pointLight({0, 0, 0}, CullFace::Back)), CullBucket::Cw);
  ShadowCaster twoSided = open;
  twoSided.doubleSided = true;
  EXPECT_EQ(cullBucket(twoSided, pointLight({0, 0, 0}, CullFace::Back)), CullBucket::None);
}

TEST(CasterCulling, ClosedSolidsSeenFromOutsideDropTheirBackFaces) {
  const ShadowCullingLight light = pointLight({0, 0, 0}, CullFace::None);
  ShadowCaster solid;
  solid.center = {5, 0, 0};
  solid.radius = 1.0f;
  solid.closed = true;
  EXPECT_TRUE(seesOnlyFrontFaces(solid, light));
  EXPECT_EQ(cullBucket(solid, light), CullBucket::Ccw);
  solid.mirrored = true;
  EXPECT_EQ(cullBucket(solid, light), CullBucket::Cw);

  // The light inside the solid, or the near plane's corners reaching into it: both sides.
  ShadowCaster around = solid;
  around.center = {0.5f, 0, 0};
  EXPECT_FALSE(seesOnlyFrontFaces(around, light));
  ShadowCaster grazing = solid;
  grazing.center = {1.1f, 0, 0};  // 0.1 from the light; the near corner reaches 0.1 * sqrt(3)
  EXPECT_FALSE(seesOnlyFrontFaces(grazing, light));
  grazing.center = {1.2f, 0, 0};
  EXPECT_TRUE(seesOnlyFrontFaces(grazing, light));

  // Alpha-tested solids have holes; a double-sided material alone does not matter.
  ShadowCaster masked = solid;
  masked.masked = true;
  EXPECT_EQ(cullBucket(masked, light), CullBucket::None);
  ShadowCaster twoSided = solid;
  twoSided.doubleSided = true;
  twoSided.mirrored = false;
  EXPECT_EQ(cullBucket(twoSided, light), CullBucket::Ccw);

  // Directional depth ranges hold the whole scene: always outside.
  ShadowCullingLight sun;
  sun.type = LightType::Directional;
  EXPECT_TRUE(seesOnlyFrontFaces(around, sun));
}

TEST(ShadowDraws, FaceRunsAreConsecutiveSetBits) {
  std::vector<std::pair<int, int>> runs;
  forEachFaceRun(0b101101u, 6, [&](int first, int count) { runs.push_back({first, count}); });
  EXPECT_EQ(runs, (std::vector<std::pair<int, int>>{{0, 1}, {2, 2}, {5, 1}}));
  runs.clear();
  forEachFaceRun(0b1000000u, 6, [&](int first, int count) { runs.push_back({first, count}); });
  EXPECT_TRUE(runs.empty());  // bits beyond the views are ignored
}

TEST(ShadowDraws, BatchesPerViewBucketAndSource) {
  std::vector<ShadowCaster> casters(4);
  casters[2].masked = true;
  std::vector<CasterGeometry> geometry = {
      {30, 0, 0, -1}, {60, 30, 100, 500}, {90, 90, 200, -1}, {120, 180, 300, -1}};
  CasterCulling culling;
  culling.viewMask = {0b000011u, 0b000010u, 0b000001u, 0u};
  culling.bucket = {CullBucket::Ccw, CullBucket::None, CullBucket::None, CullBucket::None};

  const ShadowDrawList perView =
      buildShadowDraws(casters, geometry, culling, 6, ShadowLayering::PerView);
  // View 0: caster 0 (Ccw, scene vertices); view 1: caster 1 (None, world stream), caster 0.
  ASSERT_EQ(perView.opaque.size(), 3u);
  EXPECT_EQ(perView.opaque[0].view, 0);
  EXPECT_EQ(perView.opaque[0].bucket, CullBucket::Ccw);
  EXPECT_FALSE(perView.opaque[0].world);
  EXPECT_EQ(perView.opaque[1].view, 1);
  EXPECT_EQ(perView.opaque[1].bucket, CullBucket::None);
  EXPECT_TRUE(perView.opaque[1].world);
  EXPECT_EQ(perView.opaque[2].view, 1);
  EXPECT_EQ(perView.objects, (std::vector<std::uint32_t>{0, 1, 0}));
  EXPECT_EQ(perView.commands[1].firstIndex, 500u);  // world stream copy: its own indices
  EXPECT_EQ(perView.commands[1].baseVertex, 0);
  EXPECT_EQ(perView.commands[1].count, 60u);
  ASSERT_EQ(perView.masked.size(), 1u);
  EXPECT_EQ(perView.masked[0].view, 0);
  EXPECT_EQ(perView.masked[0].caster, 2);
  EXPECT_EQ(perView.masked[0].instances, 1u);

  const ShadowDrawList instanced =
      buildShadowDraws(casters, geometry, culling, 6, ShadowLayering::Instanced);
  ASSERT_EQ(instanced.commands.size(), 2u);
  EXPECT_EQ(instanced.opaque[0].view, -1);
  EXPECT_EQ(instanced.commands[1].instanceCount, 2u);  // caster 0 on faces 0 and 1
  EXPECT_EQ(instanced.commands[1].baseInstance, 0u);
  EXPECT_EQ(instanced.commands[0].instanceCount, 1u);  // caster 1 on face 1
  EXPECT_EQ(instanced.commands[0].baseInstance, 1u);
  ASSERT_EQ(instanced.masked.size(), 1u);
  EXPECT_EQ(instanced.masked[0].instances, 0b000001u);

  const ShadowDrawList geometryShader =
      buildShadowDraws(casters, geometry, culling, 6, ShadowLayering::Geometry);
  ASSERT_EQ(geometryShader.commands.size(), 2u);
  for (const IndirectDrawCommand& c : geometryShader.commands) {
    EXPECT_EQ(c.instanceCount, 1u);
    EXPECT_EQ(c.baseInstance, 0u);
  }
}

// World-space copies that follow each other in the caster stream and go to the same faces share
// one command; the stream's order (when asked for) decides which copies follow each other, and
// a caster between them that is not drawn, or goes to other faces, splits the run.
TEST(ShadowDraws, NeighboursInTheStreamShareACommand) {
  // Stream order: caster 2 (indices 0-29), caster 0 (30-89), caster 3 (90-179), caster 1
  // (180-299), caster 4 (300-329).
  std::vector<ShadowCaster> casters(5);
  std::vector<CasterGeometry> geometry = {
      {60, 0, 0, 30}, {120, 0, 0, 180}, {30, 0, 0, 0}, {90, 0, 0, 90}, {30, 0, 0, 300}};
  CasterCulling culling;
  culling.viewMask = {0b01u, 0b01u, 0b01u, 0b01u, 0b10u};
  culling.bucket.assign(5, CullBucket::Ccw);

  const ShadowDrawList streamed =
      buildShadowDraws(casters, geometry, culling, 6, ShadowLayering::PerView, true);
  // View 0: casters 2, 0, 3, 1 are indices 0-299, one command; view 1: caster 4 alone.
  ASSERT_EQ(streamed.commands.size(), 2u);
  EXPECT_EQ(streamed.commands[0].firstIndex, 0u);
  EXPECT_EQ(streamed.commands[0].count, 300u);
  EXPECT_EQ(streamed.commands[1].firstIndex, 300u);
  EXPECT_EQ(streamed.commands[1].count, 30u);
  ASSERT_EQ(streamed.opaque.size(), 2u);
  EXPECT_EQ(streamed.opaque[0].count, 1);

  // In the casters' order (0, 1, 2, 3 in view 0) no caster's indices follow the previous one's:
  // every caster is its own command.
  const ShadowDrawList ordered =
      buildShadowDraws(casters, geometry, culling, 6, ShadowLayering::PerView, false);
  ASSERT_EQ(ordered.commands.size(), 5u);
  EXPECT_EQ(ordered.objects, (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));

  // Caster 3 off view 0 splits the run in two: 2 and 0 (0-89), then 1 (180-299).
  culling.viewMask[3] = 0b10u;
  const ShadowDrawList split =
      buildShadowDraws(casters, geometry, culling, 6, ShadowLayering::PerView, true);
  ASSERT_EQ(split.opaque.size(), 2u);
  ASSERT_EQ(split.opaque[0].count, 2);
  EXPECT_EQ(split.commands[0].count, 90u);
  EXPECT_EQ(split.commands[1].firstIndex, 180u);
  // View 1: caster 3 (90-179), then caster 4 (300-329): not neighbours.
  EXPECT_EQ(split.opaque[1].count, 2);

  // Instanced: the same faces merge, other faces do not.
  culling.viewMask = {0b11u, 0b11u, 0b11u, 0b01u, 0b11u};
  const ShadowDrawList instanced =
      buildShadowDraws(casters, geometry, culling, 6, ShadowLayering::Instanced, true);
  // Stream: 2 and 0 (faces 0-1) merge; 3 (face 0) alone; 1 and 4 (faces 0-1; 1 ends where 4
  // starts) merge.
  ASSERT_EQ(instanced.commands.size(), 3u);
  EXPECT_EQ(instanced.commands[0].count, 90u);
  EXPECT_EQ(instanced.commands[0].instanceCount, 2u);
  EXPECT_EQ(instanced.commands[1].count, 90u);
  EXPECT_EQ(instanced.commands[1].instanceCount, 1u);
  EXPECT_EQ(instanced.commands[2].firstIndex, 180u);
  EXPECT_EQ(instanced.commands[2].count, 150u);
}

namespace {

// A floor (y = 0, facing up) under a room 2 m high.
MeshPlane floorPlane() {
  return MeshPlane{{0.0f, 1.0f, 0.0f}, 0.0f, 0.0f};
}

Bounds room(float bottom = 0.0f) {
  Bounds b;
  b.extend(glm::vec3(-3.0f, bottom, -3.0f));
  b.extend(glm::vec3(3.0f, 2.0f, 3.0f));
  return b;
}

}  // namespace

TEST(FlatCasters, AFloorWithEveryReceiverAboveItShadowsNothingFromALightAbove) {
  EXPECT_TRUE(shadowsNoReceiver(floorPlane(), pointLight({0.5f, 1.8f, 0.0f}), room()));
  // Receivers a rounding below the floor (a box resting on it) still count as above.
  EXPECT_TRUE(shadowsNoReceiver(floorPlane(), pointLight({0.5f, 1.8f, 0.0f}), room(-1e-6f)));
  // The ceiling (y = 2, facing down) from the same light.
  const MeshPlane ceiling{{0.0f, -1.0f, 0.0f}, 2.0f, 0.0f};
  EXPECT_TRUE(shadowsNoReceiver(ceiling, pointLight({0.5f, 1.8f, 0.0f}), room()));
}

TEST(FlatCasters, AFloorIsKeptWhenSomethingCanBeBehindIt) {
  // A receiver 1 cm under the floor: the floor shadows it.
  EXPECT_FALSE(shadowsNoReceiver(floorPlane(), pointLight({0.5f, 1.8f, 0.0f}), room(-0.01f)));
  // The light under the floor: everything in the room is behind it.
  EXPECT_FALSE(shadowsNoReceiver(floorPlane(), pointLight({0.5f, -1.0f, 0.0f}), room()));
  // The light in the floor's plane: no side to trust.
  EXPECT_FALSE(shadowsNoReceiver(floorPlane(), pointLight({0.5f, 0.0f, 0.0f}), room()));
  // A thick floor (1 cm of thickness) with the light 5 mm above it.
  const MeshPlane thick{{0.0f, 1.0f, 0.0f}, 0.0f, 0.01f};
  EXPECT_FALSE(shadowsNoReceiver(thick, pointLight({0.5f, 0.005f, 0.0f}), room()));
  // Unknown receivers: keep everything.
  EXPECT_FALSE(shadowsNoReceiver(floorPlane(), pointLight({0.5f, 1.8f, 0.0f}), Bounds{}));
}

TEST(FlatCasters, DirectionalLightsTakeTheSideTheyComeFrom) {
  ShadowCullingLight sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));  // shining down
  EXPECT_TRUE(shadowsNoReceiver(floorPlane(), sun, room()));
  sun.direction = -sun.direction;  // shining up through the floor
  EXPECT_FALSE(shadowsNoReceiver(floorPlane(), sun, room()));
  sun.direction = glm::vec3(1.0f, 0.0f, 0.0f);  // along the floor
  EXPECT_FALSE(shadowsNoReceiver(floorPlane(), sun, room()));
}

TEST(FlatCasters, CullingLeavesOutOnlyTheFlatCastersThatShadowNothing) {
  const ShadowCullingLight light = pointLight({0.5f, 1.8f, 0.0f});
  ShadowCaster floor;
  floor.center = glm::vec3(0.0f);
  floor.radius = 4.3f;
  floor.plane = floorPlane();
  ShadowCaster box;  // resting on the floor, not flat
  box.center = glm::vec3(1.0f, 0.25f, 1.0f);
  box.radius = 0.45f;
  ShadowCaster partition = floor;  // a wall across the room at x = 1, the light on its -x side
  partition.center = glm::vec3(1.0f, 1.0f, 0.0f);
  partition.plane = MeshPlane{{1.0f, 0.0f, 0.0f}, -1.0f, 0.0f};
  const CasterCulling culling = cullCasters({floor, box, partition}, light, room());
  EXPECT_EQ(culling.viewMask[0], 0u);
  EXPECT_NE(culling.viewMask[1], 0u);
  EXPECT_NE(culling.viewMask[2], 0u);  // the room goes on behind it
  EXPECT_EQ(culling.flatLeftOut, 1);
  // Without receivers (maps that are read back) every caster is drawn.
  EXPECT_NE(cullCasters({floor, box, partition}, light, Bounds{}).viewMask[0], 0u);
}

}  // namespace caster_culling_test
