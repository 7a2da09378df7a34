// Debugging outputs for directional and spot lights (issue 18): the cascade debug view, light
// views and depth dumps of spot maps and cascades.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/core/errors.h"
#include "renderer/render/renderer.h"
#include "renderer/view/camera.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace light_debug_test {

using namespace omnishadow;

namespace {

using test_support::sharedRenderer;

// A 60 m floor seen from 1.5 m above one end, looking along it.
struct LongFloor {
  Scene scene;
  ViewCamera camera;
  LongFloor() {
    test::placeMesh(scene, builder::makePlane(60.0f), glm::mat4(1.0f), -1);
    CameraRequest request;
    request.eye = glm::vec3(0.0f, 1.5f, 29.0f);
    request.target = glm::vec3(0.0f, 0.0f, 0.0f);
    request.up = glm::vec3(0.0f, 1.0f, 0.0f);
    request.fovDegrees = 60.0f;
    request.width = 64;
    request.height = 96;
    camera = resolveCamera(scene, request);
  }
};

Light sunWithCascades(int cascades) {
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.2f));
  sun.shadow.cascades = cascades;
  sun.shadow.resolution = 256;
  return sun;
}

// Which hue dominates a pixel: 0 red, 1 green, 2 blue, -1 grey or nothing.
int dominantHue(const FloatImage& image, int x, int y) {
  const float r = image.at(x, y, 0), g = image.at(x, y, 1), b = image.at(x, y, 2);
  if (r > 1.5f * g && r > 1.5f * b) return 0;
  if (g > 1.5f * r && g > 1.5f * b) return 1;
  if (b > 1.5f * r && b > 1.5f * g) return 2;
  return -1;
}

}  // namespace

// Up the middle column, from the nearest floor to the horizon: cascade 0 (red), then 1
// (green), then 2 (blue), never back to a nearer one.
TEST(CascadeDebugView, ColorsTheFloorByCascadeFromNearToFar) {
  const LongFloor floor;
  RenderSettings settings;
  settings.debugView = DebugView::Cascade;
  StageTimes times;
  const Frame frame = sharedRenderer().render(floor.scene, {sunWithCascades(3)}, glm::vec3(0.03f),
                                              floor.camera, settings, times);
  const int x = frame.beauty.width / 2;
  std::vector<int> seen;
  for (int y = frame.beauty.height - 1; y >= 0; --y) {
    if (!(frame.beauty.at(x, y, 3) > 0.0f)) continue;  // sky
    const int hue = dominantHue(frame.beauty, x, y);
    ASSERT_GE(hue, 0) << "row " << y;
    if (seen.empty() || seen.back() != hue) seen.push_back(hue);
  }
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2}));
}

TEST(CascadeDebugView, NeedsAShadowedDirectionalLight) {
  const LongFloor floor;
  Light lamp;
  lamp.name = "lamp";
  lamp.position = {0.0f, 3.0f, 0.0f};
  RenderSettings settings;
  settings.debugView = DebugView::Cascade;
  StageTimes times;
  try {
    sharedRenderer().render(floor.scene, {lamp}, glm::vec3(0.03f), floor.camera, settings, times);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--debug-view cascade: no directional light casts a shadow");
  }
}

// --light-views for spot and directional lights: a red box under a spot light on a grey floor
// is in the middle of the spot's view (the map's own projection), and a sun with two cascades
// gives one view per cascade.
TEST(PlanarLightViews, SpotAndCascadesHaveViewsAndDepthDumps) {
  Scene scene;
  Material grey, red;
  grey.baseColorFactor = {0.6f, 0.6f, 0.6f, 1.0f};
  red.baseColorFactor = {0.9f, 0.05f, 0.05f, 1.0f};
  grey.metallicFactor = red.metallicFactor = 0.0f;
  scene.materials = {grey, red};
  auto add = [&](const builder::MeshData& d, const glm::mat4& world, int material) {
    test::placeMesh(scene, d, world, material);
  };
  add(builder::makePlane(10.0f), glm::mat4(1.0f), 0);
  add(builder::makeBox({0.3f, 0.3f, 0.3f}), glm::translate(glm::mat4(1.0f), {1.0f, 0.3f, 0.0f}), 1);
  Light spot;
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.position = {1.0f, 4.0f, 0.0f};
  spot.direction = {0.0f, -1.0f, 0.0f};
  spot.outerConeAngle = 0.6f;
  spot.intensity = 30.0f;
  Light sun = sunWithCascades(2);
  CameraRequest request;
  request.width = 64;
  request.height = 48;
  const ViewCamera camera = resolveCamera(scene, request);
  RenderSettings settings;
  settings.lightViewSize = 32;
  settings.readShadowMaps = true;
  StageTimes times;
  const Frame frame =
      sharedRenderer().render(scene, {spot, sun}, glm::vec3(0.03f), camera, settings, times);
  ASSERT_EQ(frame.lightViews.size(), 3u);
  EXPECT_EQ(frame.lightViews[0].light, "spot");
  EXPECT_EQ(frame.lightViews[0].planar, "spot");
  EXPECT_EQ(frame.lightViews[1].planar, "cascade0");
  EXPECT_EQ(frame.lightViews[2].planar, "cascade1");
  // --dump-depth: the spot map holds the box top (3.4 m along its axis) under the light and
  // the floor (4 m) near the cone's edge; each cascade has its own map.
  ASSERT_EQ(frame.planarShadowMaps.size(), 3u);
  const PlanarShadowMapDump& map = frame.planarShadowMaps[0];
  EXPECT_EQ(map.planar, "spot");
  ASSERT_EQ(map.resolution, spot.shadow.resolution);
  const int n = map.resolution;
  EXPECT_NEAR(map.distances[static_cast<std::size_t>(n / 2) * n + n / 2], 3.4f, 0.01f);
  EXPECT_NEAR(map.distances[static_cast<std::size_t>(n / 2) * n + n / 8], 4.0f, 0.01f);
  EXPECT_EQ(frame.planarShadowMaps[1].planar, "cascade0");
  EXPECT_EQ(frame.planarShadowMaps[2].planar, "cascade1");
  const FloatImage& view = frame.lightViews[0].beauty;
  ASSERT_EQ(view.width, 32);
  ASSERT_EQ(view.height, 32);
  EXPECT_GT(view.at(16, 16, 0), 4.0f * view.at(16, 16, 1));  // the red box top
  // Near the edge of the cone: the lit grey floor.
  const float r = view.at(16, 4, 0), g = view.at(16, 4, 1);
  EXPECT_GT(g, 0.0f);
  EXPECT_NEAR(r / g, 1.0f, 0.05f);
}

}  // namespace light_debug_test
