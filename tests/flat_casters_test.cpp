// Flat casters that shadow nothing (shadowsNoReceiver, renderer/view/caster_culling.h): a floor
// with the whole scene above it and the light above too is left out of the shadow maps the
// lighting samples, which changes no shadow, and is kept where something lies under it and in
// maps that are read back.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "renderer/render/renderer.h"
#include "renderer/view/cube_faces.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace flat_casters_test {

using namespace omnishadow;
using test_support::lookFrom;
using test_support::sharedRenderer;

namespace {

int addMaterial(Scene& scene, glm::vec4 color) {
  Material m;
  m.baseColorFactor = color;
  m.metallicFactor = 0.0f;
  m.roughnessFactor = 0.6f;
  scene.materials.push_back(m);
  return static_cast<int>(scene.materials.size()) - 1;
}

glm::mat4 at(glm::vec3 t) {
  return glm::translate(glm::mat4(1.0f), t);
}

// An 8 m floor at y = 0 with a sphere floating over it and a box resting on it.
Scene floorScene() {
  Scene scene;
  const int grey = addMaterial(scene, glm::vec4(0.7f, 0.7f, 0.7f, 1.0f));
  test::placeMesh(scene, builder::makePlane(8.0f, 4), glm::mat4(1.0f), grey);
  test::placeMesh(scene, builder::makeSphere(0.5f, 32, 16), at({-0.6f, 1.2f, 0.2f}), grey);
  test::placeMesh(scene, builder::makeBox(glm::vec3(0.3f)), at({0.9f, 0.3f, -0.4f}), grey);
  return scene;
}

Light lampAt(glm::vec3 position, ShadowFilter filter = ShadowFilter::Pcf) {
  Light light;
  light.name = "lamp";
  light.position = position;
  light.intensity = 20.0f;
  light.shadow.resolution = 256;
  light.shadow.filter = filter;
  return light;
}

Frame render(const Scene& scene, const Light& light, const ViewCamera& camera,
             bool readShadowMaps) {
  RenderSettings settings;
  settings.aovs = true;
  settings.readShadowMaps = readShadowMaps;
  StageTimes times;
  return sharedRenderer().render(scene, {light}, glm::vec3(0.02f), camera, settings, times);
}

}  // namespace

TEST(FlatCasters, AFloorUnderEverythingIsLeftOutAndNoShadowChanges) {
  const Scene scene = floorScene();
  const ViewCamera camera = lookFrom(scene, {0.0f, 4.0f, 5.0f}, {0.0f, 0.3f, 0.0f}, 96, 72);
  for (const ShadowFilter filter : {ShadowFilter::Hard, ShadowFilter::Pcf, ShadowFilter::Poisson}) {
    const Light lamp = lampAt({0.3f, 3.0f, 0.5f}, filter);
    const Frame culled = render(scene, lamp, camera, false);
    const Frame complete = render(scene, lamp, camera, true);
    EXPECT_EQ(culled.flatCastersLeftOut, 1);
    EXPECT_EQ(complete.flatCastersLeftOut, 0);
    EXPECT_EQ(culled.shadowMapsRendered, 1);
    EXPECT_EQ(complete.shadowMapsRendered, 1);  // not the culled maps again
    // The sphere's shadow on the floor and the box's at its foot, texel for texel the same.
    ASSERT_EQ(culled.aovs->pixels.size(), complete.aovs->pixels.size());
    EXPECT_EQ(culled.aovs->pixels, complete.aovs->pixels) << static_cast<int>(filter);
    int shadowed = 0;
    const int v = culled.aovs->channelIndex("visibility.lamp");
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) shadowed += culled.aovs->at(x, y, v) == 0.0f;
    EXPECT_GT(shadowed, 50);
  }
}

TEST(FlatCasters, AFloorStillShadowsWhatLiesUnderIt) {
  // A second floor 1 m under the first, seen from between the two: the light above reaches it
  // only through the upper floor, which must then be drawn.
  Scene scene = floorScene();
  const int white = addMaterial(scene, glm::vec4(0.9f, 0.9f, 0.9f, 1.0f));
  test::placeMesh(scene, builder::makePlane(2.0f, 2), at({0.0f, -1.0f, 0.0f}), white);
  const ViewCamera camera = lookFrom(scene, {0.0f, -0.4f, 1.2f}, {0.0f, -1.0f, 0.0f}, 64, 48);
  const Frame frame = render(scene, lampAt({0.3f, 3.0f, 0.5f}), camera, false);
  // Only the lower floor, with everything above it, is left out.
  EXPECT_EQ(frame.flatCastersLeftOut, 1);
  const int p = frame.aovs->channelIndex("P.Y");
  const int a = frame.aovs->channelIndex("A");
  const int v = frame.aovs->channelIndex("visibility.lamp");
  int lower = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      if (frame.aovs->at(x, y, a) < 1.0f || std::abs(frame.aovs->at(x, y, p) + 1.0f) > 1e-3f)
        continue;
      ++lower;
      EXPECT_EQ(frame.aovs->at(x, y, v), 0.0f) << x << "," << y;
    }
  EXPECT_GT(lower, 500);
}

TEST(FlatCasters, DumpsAfterAPlainRenderHoldTheFloor) {
  // The plain render leaves the floor out of its maps; the dump that follows, of the same
  // scene and light, must not take those maps from the cache.
  const Scene scene = floorScene();
  const ViewCamera camera = lookFrom(scene, {0.0f, 4.0f, 5.0f}, {0.0f, 0.3f, 0.0f}, 48, 36);
  const Light lamp = lampAt({0.3f, 3.0f, 0.5f});
  render(scene, lamp, camera, false);
  const Frame dumped = render(scene, lamp, camera, true);
  ASSERT_EQ(dumped.shadowMaps.size(), 1u);
  const CubeDistances& map = dumped.shadowMaps[0].distances;
  // Straight down from the lamp (the -Y face's centre) the floor is 3 m away.
  const int middle = map.resolution / 2;
  EXPECT_NEAR(map.at(CubeFace::NegY, middle, middle), 3.0f, 0.05f);
}

TEST(FlatCasters, ReceiversDrawnPerVertexCountToo) {
  // 150 instances of one sphere are too many vertices to copy into the world-space caster
  // stream; they are drawn from the mesh with a transform each, and hang under the floor.
  Scene scene = floorScene();
  const builder::MeshData ball = builder::makeSphere(0.05f, 32, 16);
  test::placeMesh(scene, ball, at({0.0f, -1.0f, 0.0f}), 0);
  const int mesh = static_cast<int>(scene.meshes.size()) - 1;
  for (int i = 1; i < 150; ++i) {
    const glm::mat4 world = at({0.1f * static_cast<float>(i % 12) - 0.6f, -1.0f,
                                0.1f * static_cast<float>(i / 12) - 0.6f});
    scene.instances.push_back({mesh, world, -1, {}, {}});
    scene.bounds.extend(scene.meshes.back().bounds.transformed(world));
  }
  ASSERT_GT(150 * ball.positions.size(), std::size_t{1} << 16);
  const ViewCamera camera = lookFrom(scene, {0.0f, -0.4f, 1.2f}, {0.0f, -1.0f, 0.0f}, 32, 24);
  EXPECT_EQ(render(scene, lampAt({0.3f, 3.0f, 0.5f}), camera, false).flatCastersLeftOut, 0);
}

}  // namespace flat_casters_test
