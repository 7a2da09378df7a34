// Screen-space ambient occlusion (AmbientOcclusion) checked against what the geometry gives: the
// cosine-weighted share of the hemisphere a wall hides from a floor, open surfaces left exactly
// as they were, the ambient light darkened by the estimate and the punctual lights not, and the
// surfaces the estimate is not for left alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/verify/ambient_occlusion_reference.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::ambient_occlusion_test {
namespace {

using test_support::lookFrom;
using test_support::sharedRenderer;

constexpr float kPi = 3.14159265358979f;

Material matte(glm::vec3 base, AlphaMode mode = AlphaMode::Opaque) {
  Material m;
  m.baseColorFactor = glm::vec4(base, 1.0f);
  m.metallicFactor = 0.0f;
  m.roughnessFactor = 1.0f;
  m.doubleSided = true;
  m.alphaMode = mode;
  return m;
}

// A floor (y = 0, 40 x 40) and a wall (x = 0, facing +X, 40 wide and 20 high).
Scene floorAndWall() {
  Scene scene;
  scene.materials.push_back(matte(glm::vec3(0.8f)));
  test::placeMesh(scene, builder::makePlane(40.0f), glm::mat4(1.0f), 0);
  const glm::mat4 wall = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 10.0f, 0.0f)) *
                         glm::rotate(glm::mat4(1.0f), -kPi / 2.0f, glm::vec3(0, 0, 1));
  test::placeMesh(scene, builder::makePlane(20.0f), wall, 0);
  return scene;
}

Frame render(const Scene& scene, const Ambience& ambience, const ViewCamera& camera,
             RenderSettings settings = {}, const std::vector<Light>& lights = {}) {
  StageTimes times;
  return sharedRenderer().render(scene, lights, ambience, camera, settings, times);
}

Ambience occluded(glm::vec3 ambient, float radius, float strength = 1.0f) {
  Ambience ambience(ambient);
  ambience.ambientOcclusion = AmbientOcclusion{radius, strength};
  return ambience;
}

// The occlusion debug view: the share of the ambient light each pixel's surface receives.
Frame occlusionView(const Scene& scene, const Ambience& ambience, const ViewCamera& camera,
                    RenderSettings settings = {}) {
  settings.debugView = DebugView::Occlusion;
  return render(scene, ambience, camera, settings);
}

// The cosine-weighted share of the hemisphere above a floor point `d` from an endless wall that
// rays reaching it within `reach` hit (directions by azimuth from the wall's normal and angle
// from the floor's normal, integrated numerically).
float visibleNearWall(float d, float reach) {
  constexpr int kSteps = 200;
  double hidden = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double theta = (i + 0.5) / kSteps * (kPi / 2.0);
    for (int j = 0; j < kSteps; ++j) {
      const double phi = (j + 0.5) / kSteps * kPi - kPi / 2.0;  // towards the wall
      const double towards = std::sin(theta) * std::cos(phi);
      if (towards <= 0.0 || d / towards >= reach) continue;
      hidden += std::cos(theta) * std::sin(theta) * (kPi / 2.0 / kSteps) * (kPi / kSteps);
    }
  }
  return static_cast<float>(1.0 - hidden / kPi);
}

// Where the wall lies within the radius, the estimate lies in the share the geometry gives with
// the radius cut off between where the falloff starts (0.8) and ends (1), to 0.04 (depth-buffer
// sampling of 12 slices and eight steps a side; at most 0.032 over more than 800 pixels):
// screen-space estimates fall short of the truth, never beyond it. Beyond the radius nothing is
// occluded: exactly 1, but for pixels whose nearest estimates reach the nearer floor.
void expectTheWallsShare(const Scene& scene, const ViewCamera& camera, int minimumNear) {
  const float radius = 1.0f;
  RenderSettings settings;
  settings.aovs = true;
  const Frame positions = render(scene, glm::vec3(0.1f), camera, settings);
  const Frame view = occlusionView(scene, occluded(glm::vec3(0.1f), radius), camera);
  const FloatImage& aovs = *positions.aovs;
  const int px = aovs.channelIndex("P.X"), py = aovs.channelIndex("P.Y");
  int near = 0, far = 0, farUnoccluded = 0, closest = 0;
  for (int y = 0; y < 240; y += 2)
    for (int x = 64; x < 256; x += 4) {  // the wall within the radius lies in the picture
      const float* p = &aovs.pixels[(static_cast<std::size_t>(y) * 320 + x) * aovs.channels.size()];
      if (positions.beauty.at(x, y, 3) < 1.0f || std::abs(p[py]) > 1e-4f) continue;  // the floor
      const float d = p[px];
      const float got = view.beauty.at(x, y, 0);
      SCOPED_TRACE("pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), " +
                   std::to_string(d) + " from the wall");
      if (d >= radius) {
        ++far;
        farUnoccluded += got == 1.0f;
        EXPECT_GE(got, 0.99f);
        continue;
      }
      if (d < 0.15f) {  // a few pixels from the corner, where normals from depth bend
        ++closest;
        EXPECT_LT(got, 0.7f);
        continue;
      }
      ++near;
      EXPECT_LE(got, visibleNearWall(d, 0.8f * radius) + 0.04f);
      EXPECT_GE(got, visibleNearWall(d, radius) - 1e-3f);  // the integral's own error
    }
  EXPECT_GT(near, minimumNear);
  EXPECT_GT(closest, 50);
  EXPECT_GT(far, 2000);
  EXPECT_GE(farUnoccluded, far * 99 / 100);
}

TEST(AmbientOcclusion, AWallHidesWhatTheGeometrySaysFromTheFloor) {
  const Scene scene = floorAndWall();
  expectTheWallsShare(
      scene, lookFrom(scene, {5.0f, 3.0f, 0.5f}, {0.8f, 0.3f, 0.0f}, 320, 240, 50.0f), 500);
}

// An orthographic camera's view vector is the same everywhere, and its pixels as wide at every
// distance: the same shares.
TEST(AmbientOcclusion, AWallHidesTheSameSeenOrthographically) {
  const Scene scene = floorAndWall();
  ViewCamera camera = lookFrom(scene, {5.0f, 3.0f, 0.5f}, {0.8f, 0.3f, 0.0f}, 320, 240, 50.0f);
  camera.orthographic = true;
  camera.projection = reversedOrthographic(2.4f, 1.8f, 0.1f, 20.0f);
  expectTheWallsShare(scene, camera, 500);
}

// An open plane and a convex sphere hide nothing from themselves: with occlusion the picture is
// the one without, bit for bit, and so is any frame whose strength is 0.
TEST(AmbientOcclusion, OpenAndConvexSurfacesKeepTheirAmbientLight) {
  Scene scene;
  scene.materials.push_back(matte(glm::vec3(0.7f, 0.5f, 0.3f)));
  test::placeMesh(scene, builder::makePlane(10.0f), glm::mat4(1.0f), 0);
  const ViewCamera camera = lookFrom(scene, {3.0f, 2.0f, 4.0f}, {0, 0, 0}, 160, 120);
  const Frame plain = render(scene, glm::vec3(0.2f), camera);
  const Frame withOcclusion = render(scene, occluded(glm::vec3(0.2f), 2.0f), camera);
  EXPECT_EQ(withOcclusion.beauty.pixels, plain.beauty.pixels);

  Scene ball;
  ball.materials.push_back(matte(glm::vec3(0.7f)));
  test::placeMesh(ball, builder::makeSphere(1.0f, 64, 32), glm::mat4(1.0f), 0);
  const ViewCamera close = lookFrom(ball, {0.0f, 1.0f, 3.0f}, {0, 0, 0}, 128, 128);
  const Frame view = occlusionView(ball, occluded(glm::vec3(0.2f), 0.5f), close);
  // The normal from depth differences is poorest on the silhouette, where one side of the
  // pixel is empty: a few percent of occlusion there.
  const auto silhouette = [&](int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (view.beauty.at(std::clamp(x + dx, 0, 127), std::clamp(y + dy, 0, 127), 3) < 1.0f)
          return true;
    return false;
  };
  int covered = 0, unoccluded = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      if (view.beauty.at(x, y, 3) < 1.0f) continue;
      ++covered;
      unoccluded += view.beauty.at(x, y, 0) == 1.0f;
      EXPECT_GE(view.beauty.at(x, y, 0), silhouette(x, y) ? 0.9f : 0.98f) << x << ", " << y;
    }
  EXPECT_GT(covered, 4000);
  EXPECT_GE(unoccluded, covered * 95 / 100);

  const Scene corner = floorAndWall();
  const ViewCamera cornerCamera =
      lookFrom(corner, {4.0f, 2.0f, 1.0f}, {0.5f, 0.2f, 0.0f}, 160, 120);
  EXPECT_EQ(render(corner, occluded(glm::vec3(0.2f), 1.0f, 0.0f), cornerCamera).beauty.pixels,
            render(corner, glm::vec3(0.2f), cornerCamera).beauty.pixels);
}

// The estimate scales the ambient light a surface reflects, by 1 + strength (share - 1), and
// leaves the lights' own light to their shadows.
TEST(AmbientOcclusion, ItDarkensTheAmbientLightAndNotTheLights) {
  const Scene scene = floorAndWall();
  const ViewCamera camera = lookFrom(scene, {4.0f, 2.0f, 1.0f}, {0.5f, 0.2f, 0.0f}, 160, 120);
  const glm::vec3 ambient(0.25f);
  const Frame share = occlusionView(scene, occluded(ambient, 1.0f), camera);
  const Frame plain = render(scene, ambient, camera);
  for (const float strength : {1.0f, 0.5f}) {
    SCOPED_TRACE("strength " + std::to_string(strength));
    const Frame darker = render(scene, occluded(ambient, 1.0f, strength), camera);
    int occludedPixels = 0;
    for (int y = 0; y < 120; ++y)
      for (int x = 0; x < 160; ++x) {
        const float visible = share.beauty.at(x, y, 0);
        occludedPixels += visible < 0.9f;
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(darker.beauty.at(x, y, c),
                      plain.beauty.at(x, y, c) * (1.0f + strength * (visible - 1.0f)), 1e-6f)
              << x << ", " << y;
      }
    EXPECT_GT(occludedPixels, 500);
  }

  Light lamp;
  lamp.name = "lamp";
  lamp.type = LightType::Point;
  lamp.position = {2.0f, 2.0f, 1.0f};
  lamp.intensity = 20.0f;
  EXPECT_EQ(render(scene, occluded(glm::vec3(0.0f), 1.0f), camera, {}, {lamp}).beauty.pixels,
            render(scene, glm::vec3(0.0f), camera, {}, {lamp}).beauty.pixels);
}

// The occlusion AOV layer holds what the debug view shows, and 0 where no surface is.
TEST(AmbientOcclusion, TheOcclusionLayerIsTheDebugViewsShare) {
  const Scene scene = floorAndWall();
  const ViewCamera camera = lookFrom(scene, {4.0f, 2.0f, 1.0f}, {0.5f, 0.2f, 0.0f}, 160, 120);
  const Ambience ambience = occluded(glm::vec3(0.3f), 1.0f);
  RenderSettings settings;
  settings.aovs = true;
  settings.layers.occlusion = true;
  const Frame frame = render(scene, ambience, camera, settings);
  const Frame view = occlusionView(scene, ambience, camera);
  const FloatImage& aovs = *frame.aovs;
  const int channel = aovs.channelIndex("occlusion");
  ASSERT_EQ(channel, static_cast<int>(aovs.channels.size()) - 1);
  int occludedPixels = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const float layer = aovs.at(x, y, channel);
      ASSERT_EQ(aovs.at(x, y, 3), 1.0f);
      EXPECT_EQ(layer, view.beauty.at(x, y, 0)) << x << ", " << y;
      occludedPixels += layer < 0.9f;
    }
  EXPECT_GT(occludedPixels, 500);
  // Turned away from the wall, to the floor's edge and the sky above it.
  const ViewCamera away = lookFrom(scene, {2.0f, 1.0f, 0.0f}, {12.0f, 3.0f, 0.0f}, 160, 120);
  const Frame sky = render(scene, ambience, away, settings);
  int background = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      if (sky.aovs->at(x, y, 3) == 0.0f) {
        ++background;
        EXPECT_EQ(sky.aovs->at(x, y, channel), 0.0f);
      }
  EXPECT_GT(background, 1000);
  // Without ambient_occlusion, the occlusion texture's share alone: 1 here.
  const Frame open = render(scene, glm::vec3(0.3f), camera, settings);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      if (open.aovs->at(x, y, 3) > 0.0f) {
        ASSERT_EQ(open.aovs->at(x, y, channel), 1.0f);
      }
    }
}

// An AOV frame of many shadowed lights draws its lighting pass once per group of visibility
// channels; the passes after the first read the first one's estimate. Each frame's first pass
// makes its own: after a frame seen from elsewhere, the layer is still this view's share.
TEST(AmbientOcclusion, AnAovFrameOfManyLightsTakesItsOwnViewsEstimate) {
  const Scene scene = floorAndWall();
  const ViewCamera camera = lookFrom(scene, {4.0f, 2.0f, 1.0f}, {0.5f, 0.2f, 0.0f}, 160, 120);
  const ViewCamera elsewhere = lookFrom(scene, {3.0f, 4.0f, -3.0f}, {0.0f, 1.0f, 0.0f}, 160, 120);
  const Ambience ambience = occluded(glm::vec3(0.3f), 1.0f);
  std::vector<Light> lamps;
  for (int i = 0; i < 10; ++i) {
    Light lamp;
    lamp.name = "lamp" + std::to_string(i);
    lamp.type = LightType::Point;
    lamp.position = {1.0f + 0.3f * static_cast<float>(i), 2.0f,
                     -2.0f + 0.4f * static_cast<float>(i)};
    lamp.intensity = 5.0f;
    lamp.shadow.resolution = 64;
    lamps.push_back(lamp);
  }
  RenderSettings settings;
  settings.aovs = true;
  settings.layers.occlusion = true;
  const Frame before = render(scene, ambience, elsewhere, settings, lamps);
  const Frame frame = render(scene, ambience, camera, settings, lamps);
  const Frame view = occlusionView(scene, ambience, camera);
  const int channel = frame.aovs->channelIndex("occlusion");
  ASSERT_GE(channel, 0);
  int occludedPixels = 0, differentBefore = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const float layer = frame.aovs->at(x, y, channel);
      ASSERT_EQ(layer, view.beauty.at(x, y, 0)) << x << ", " << y;
      occludedPixels += layer < 0.9f;
      differentBefore += layer != before.aovs->at(x, y, channel);
    }
  EXPECT_GT(occludedPixels, 500);
  EXPECT_GT(differentBefore, 1000);  // the frame before left another estimate behind
  // The last lamp's shadow term came from a later pass than the first.
  const int last = frame.aovs->channelIndex("visibility.lamp9");
  ASSERT_GE(last, 0) << "no visibility.lamp9";
}

// The estimate is made from the depth the pre-pass draws, and drawn for itself where there is
// no pre-pass: the same frame either way, the same every time.
TEST(AmbientOcclusion, TheSameWithAndWithoutTheDepthPrepass) {
  const Scene scene = floorAndWall();
  const ViewCamera camera = lookFrom(scene, {4.0f, 2.0f, 1.0f}, {0.5f, 0.2f, 0.0f}, 160, 120);
  RenderSettings on, off;
  on.depthPrepass = DepthPrepass::On;
  off.depthPrepass = DepthPrepass::Off;
  const Ambience ambience = occluded(glm::vec3(0.3f), 1.0f);
  const Frame first = render(scene, ambience, camera, on);
  EXPECT_EQ(render(scene, ambience, camera, off).beauty.pixels, first.beauty.pixels);
  EXPECT_EQ(render(scene, ambience, camera, on).beauty.pixels, first.beauty.pixels);
  // Nor does the 8-bit beauty differ from the float one's encoding, nor the AOVs' beauty.
  RenderSettings aovs;
  aovs.aovs = true;
  const Frame withAovs = render(scene, ambience, camera, aovs);
  EXPECT_EQ(withAovs.beauty.pixels, first.beauty.pixels);
}

// Masked surfaces are in the depth the estimate is made from, but for their cut-out texels: a
// masked shelf against the wall is occluded near it as the same opaque shelf is, bit for bit,
// and the wall under it is occluded by it; a shelf cut out everywhere leaves the wall as it is
// without one. A blended shelf is not in that depth: it takes no occlusion.
TEST(AmbientOcclusion, MaskedSurfacesCastAndTakeItButForTheirCutOuts) {
  // A shelf 1 deep and 2 wide at height 1, against the wall.
  const glm::mat4 shelf = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 1.0f, 0.0f)) *
                          glm::scale(glm::mat4(1.0f), glm::vec3(0.5f, 1.0f, 1.0f));
  const auto withShelf = [&](AlphaMode mode, float alpha) {
    Scene scene = floorAndWall();
    Material material = matte(glm::vec3(0.9f), mode);
    material.baseColorFactor.a = alpha;
    scene.materials.push_back(material);
    test::placeMesh(scene, builder::makePlane(2.0f), shelf, 1);
    return scene;
  };
  const Scene opaque = withShelf(AlphaMode::Opaque, 1.0f);
  const ViewCamera camera = lookFrom(opaque, {4.0f, 3.0f, 0.0f}, {0.5f, 1.0f, 0.0f}, 160, 120);
  RenderSettings ids;
  ids.aovs = true;
  ids.layers.objectId = true;
  const Frame located = render(opaque, glm::vec3(0.2f), camera, ids);
  const int id = located.aovs->channelIndex("objectId");
  const Ambience ambience = occluded(glm::vec3(0.2f), 0.5f);
  const Frame opaqueView = occlusionView(opaque, ambience, camera);
  const Frame maskedView = occlusionView(withShelf(AlphaMode::Mask, 1.0f), ambience, camera);
  const Frame blendedView = occlusionView(withShelf(AlphaMode::Blend, 1.0f), ambience, camera);
  EXPECT_EQ(maskedView.beauty.pixels, opaqueView.beauty.pixels);
  for (const DepthPrepass prepass : {DepthPrepass::On, DepthPrepass::Off}) {
    RenderSettings settings;
    settings.depthPrepass = prepass;
    const Scene masked = withShelf(AlphaMode::Mask, 1.0f);
    EXPECT_EQ(render(masked, ambience, camera, settings).beauty.pixels,
              render(masked, ambience, camera).beauty.pixels);
  }
  int shelfPixels = 0, shelfOccluded = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * 160 + x;
      if (located.aovs->pixels[i * located.aovs->channels.size() + id] != 2.0f) continue;
      ++shelfPixels;
      shelfOccluded += opaqueView.beauty.at(x, y, 0) < 0.95f;
      // Blended over the wall's occlusion with the shelf's own 1.
      EXPECT_EQ(blendedView.beauty.at(x, y, 0), 1.0f) << x << ", " << y;
    }
  EXPECT_GT(shelfPixels, 500);
  EXPECT_GT(shelfOccluded, 100);

  // Cut out everywhere (alpha below the cutoff): the frame of the wall and floor alone.
  const Scene bare = floorAndWall();
  EXPECT_EQ(occlusionView(withShelf(AlphaMode::Mask, 0.2f), ambience, camera).beauty.pixels,
            occlusionView(bare, ambience, camera).beauty.pixels);
  EXPECT_NE(opaqueView.beauty.pixels, occlusionView(bare, ambience, camera).beauty.pixels);
}

// The ray-traced reference the real models are measured against gives the wall's share too.
TEST(AmbientOcclusion, TheRayTracedReferenceGivesTheWallsShare) {
  const Scene scene = floorAndWall();
  const ShadowReference reference(scene);
  for (const float d : {0.05f, 0.3f, 0.6f, 0.9f, 1.5f}) {
    SCOPED_TRACE("d " + std::to_string(d));
    EXPECT_NEAR(ambientVisibility(reference, {d, 0.0f, 0.3f}, {0, 1, 0}, 1.0f, 4096),
                visibleNearWall(d, 1.0f), 0.01f);
  }
}

// On models nobody here made, from seeded random views and two radii (5% and 15% of the
// diagonal): the estimate against rays from each pixel's surface (its triangle's normal, as the
// estimate's from depth) that meet any surface within 0.9 radius (the falloff's middle).
// Screen-space estimates miss what the camera does not see and take what it sees for solid to
// infinity behind it. Measured at 320 x 240, 3 views a model (the numbers in
// docs/performance.md): over all pixels the mean |error| is 0.002-0.021 and at most 0.9% of
// pixels come out darker by more than 0.25; over the pixels the rays find occluded (below 0.9)
// the estimate takes 25% (Sundial, its occluders mostly hidden) to 67% (Suzanne) of the error
// a frame without it would have, 55% of it over the five models.
TEST(AmbientOcclusion, RealModelsAgreeWithRayTracedOcclusion) {
  const std::string root = std::string(OMNISHADOW_SOURCE_DIR) + "/scenes/thirdparty/";
  std::mt19937 random(20261129u);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  double allOccludedAbsolute = 0.0, allOccludedShare = 0.0;
  for (const std::string model :
       {"CornellBoxSuzanne/cornell-box.glb", "Sundial/Sundial.glb", "WhackAMole/WhackAMole.glb",
        "Duck/Duck.glb", "Suzanne/Suzanne.gltf"}) {
    const Scene scene = loadGltf(root + model);
    // The debug view is then the estimate alone, not times an occlusion texture.
    for (const Material& material : scene.materials)
      ASSERT_LT(material.occlusionTexture.texture, 0);
    const ShadowReference reference(scene);
    double sumError = 0.0, sumAbsolute = 0.0, occludedAbsolute = 0.0, occludedShare = 0.0;
    long pixels = 0, darker = 0, lighter = 0, occludedPixels = 0;
    for (int view = 0; view < 3; ++view) {
      const float azimuth = 6.2831853f * unit(random), elevation = 0.15f + 0.9f * unit(random);
      const glm::vec3 direction(std::cos(azimuth) * std::cos(elevation), std::sin(elevation),
                                std::sin(azimuth) * std::cos(elevation));
      const glm::vec3 eye = scene.bounds.center() +
                            direction * (scene.bounds.radius() * (1.4f + 1.2f * unit(random)));
      const ViewCamera camera = lookFrom(scene, eye, scene.bounds.center(), 320, 240, 50.0f);
      RenderSettings settings;
      settings.aovs = true;
      const Frame surfaces = render(scene, glm::vec3(0.2f), camera, settings);
      const FloatImage& aovs = *surfaces.aovs;
      const int p = aovs.channelIndex("P.X");
      for (const float share : {0.05f, 0.15f}) {
        const float radius = share * 2.0f * scene.bounds.radius();
        const Frame estimate = occlusionView(scene, occluded(glm::vec3(0.2f), radius), camera);
        for (int y = 0; y < 240; ++y)
          for (int x = 0; x < 320; ++x) {
            if (aovs.at(x, y, 3) < 1.0f) continue;
            const glm::vec3 point(aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2));
            // The triangle's own normal, towards the camera, as the estimate's from depth: the
            // AOV's is the shading normal (the Cornell box's is smoothed around its corners).
            const glm::vec3 ray = glm::normalize(point - eye);
            const std::optional<SurfaceHit> hit =
                reference.intersect(eye, ray, 0.0f, glm::length(point - eye) * 1.001f);
            if (!hit) continue;
            const glm::vec3 normal = glm::dot(hit->geometricNormal, ray) < 0.0f
                                         ? hit->geometricNormal
                                         : -hit->geometricNormal;
            const float truth = ambientVisibility(reference, point, normal, 0.9f * radius);
            const float error = estimate.beauty.at(x, y, 0) - truth;
            sumError += error;
            sumAbsolute += std::abs(error);
            if (truth < 0.9f) {
              occludedAbsolute += std::abs(error);
              occludedShare += 1.0f - truth;
              ++occludedPixels;
            }
            darker += error < -0.25f;
            lighter += error > 0.25f;
            ++pixels;
          }
      }
    }
    SCOPED_TRACE(model);
    ASSERT_GT(pixels, 10000);
    EXPECT_LT(sumAbsolute / pixels, 0.04);
    EXPECT_LT(static_cast<double>(darker) / pixels, 0.02);
    ASSERT_GT(occludedPixels, 300);
    EXPECT_LT(occludedAbsolute, 0.85 * occludedShare);
    allOccludedAbsolute += occludedAbsolute;
    allOccludedShare += occludedShare;
    std::printf(
        "%-36s pixels %6ld  mean error %+.4f  mean |error| %.4f  darker by >0.25 %.4f  "
        "lighter by >0.25 %.4f  occluded (rays < 0.9) %6ld  their mean |error| %.4f (of %.4f)\n",
        model.c_str(), pixels, sumError / pixels, sumAbsolute / pixels,
        static_cast<double>(darker) / pixels, static_cast<double>(lighter) / pixels, occludedPixels,
        occludedAbsolute / std::max(occludedPixels, 1L),
        occludedShare / std::max(occludedPixels, 1L));
  }
  EXPECT_LT(allOccludedAbsolute, 0.6 * allOccludedShare);
}

}  // namespace
}  // namespace omnishadow::ambient_occlusion_test
