// Shadow maps drawn in two GL contexts at once (RenderSettings::parallelShadowMaps,
// passes/shadow_worker.h) are the maps one context draws: for every light type and filter, each
// shadow pass strategy, opaque, alpha-tested and translucent casters, byte for byte in the maps
// as read back, the beauty and the AOVs.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/gl/software_rasterizer.h"
#include "renderer/render/renderer.h"
#include "tests/support/shadow_stage.h"
#include "tests/support/shared_renderer.h"

namespace parallel_shadow_maps_test {

using namespace omnishadow;
using test_support::lookFrom;

namespace {

Light shadowed(const std::string& name, LightType type, glm::vec3 position, ShadowFilter filter,
               int resolution) {
  Light light;
  light.name = name;
  light.type = type;
  light.position = position;
  light.direction = glm::normalize(-position);
  light.intensity = type == LightType::Directional ? 2.0f : 15.0f;
  light.outerConeAngle = 0.9f;
  light.shadow.filter = filter;
  light.shadow.resolution = resolution;
  light.shadow.radius = 0.2f;
  return light;
}

// Six shadowed lights, every type and filter; `shift` moves them so that no map of the frame
// before can be reused.
std::vector<Light> rig(float shift) {
  return {
      shadowed("pcf", LightType::Point, {1.0f + shift, 3.0f, 0.5f}, ShadowFilter::Pcf, 128),
      shadowed("vsm", LightType::Point, {-2.0f, 2.5f + shift, 1.0f}, ShadowFilter::Vsm, 64),
      shadowed("spot", LightType::Spot, {0.5f, 4.0f, -2.0f + shift}, ShadowFilter::Pcss, 128),
      shadowed("sun", LightType::Directional, {0.3f + shift, 1.0f, 0.2f}, ShadowFilter::Hard, 256),
      shadowed("disk", LightType::Point, {-1.5f, 3.5f, -1.5f + shift}, ShadowFilter::Poisson, 96),
      shadowed("rim", LightType::Spot, {2.5f, 2.0f + shift, 2.5f}, ShadowFilter::PcfDisk, 128)};
}

void expectSameFrames(const Frame& one, const Frame& two) {
  EXPECT_EQ(one.beauty.pixels, two.beauty.pixels);
  ASSERT_TRUE(one.aovs && two.aovs);
  EXPECT_EQ(one.aovs->pixels, two.aovs->pixels);
  ASSERT_EQ(one.shadowMaps.size(), two.shadowMaps.size());
  for (std::size_t i = 0; i < one.shadowMaps.size(); ++i)
    EXPECT_EQ(one.shadowMaps[i].distances.faces, two.shadowMaps[i].distances.faces)
        << one.shadowMaps[i].light;
  ASSERT_EQ(one.planarShadowMaps.size(), two.planarShadowMaps.size());
  for (std::size_t i = 0; i < one.planarShadowMaps.size(); ++i)
    EXPECT_EQ(one.planarShadowMaps[i].distances, two.planarShadowMaps[i].distances)
        << one.planarShadowMaps[i].light << " " << one.planarShadowMaps[i].planar;
}

}  // namespace

TEST(ParallelShadowMaps, DrawTheSameMapsAndPicturesAsOneContext) {
  // A renderer of its own: its first frame is drawn in one context whatever the settings say.
  Renderer renderer(ContextOptions{});
  const Scene scene = test_support::shadowStage();
  const ViewCamera camera = lookFrom(scene, {0.0f, 5.0f, 6.0f}, {0.0f, 0.5f, 0.0f}, 96, 64);
  StageTimes times;
  RenderSettings settings;
  settings.aovs = true;
  const Frame first = renderer.render(scene, rig(0.0f), glm::vec3(0.03f), camera, settings, times);
  EXPECT_EQ(first.shadowMapsInParallel, 0);
  EXPECT_EQ(first.shadowMapsRendered, 6);
  const bool software = gl::isLlvmpipe(renderer.glDescription());

  for (const ShadowPassStrategy strategy :
       {ShadowPassStrategy::Auto, ShadowPassStrategy::Geometry, ShadowPassStrategy::Instanced}) {
    for (const bool readBack : {false, true}) {  // read-back maps hold every caster
      SCOPED_TRACE(::testing::Message() << "strategy " << static_cast<int>(strategy)
                                        << (readBack ? ", maps read back" : ""));
      settings.shadowPass = strategy;
      settings.readShadowMaps = readBack;
      RenderSettings serial = settings;
      serial.parallelShadowMaps = false;
      const Frame one = renderer.render(scene, rig(0.1f), glm::vec3(0.03f), camera, serial, times);
      EXPECT_EQ(one.shadowMapsInParallel, 0);
      renderer.render(scene, rig(0.2f), glm::vec3(0.03f), camera, settings, times);
      const Frame two =
          renderer.render(scene, rig(0.1f), glm::vec3(0.03f), camera, settings, times);
      EXPECT_EQ(two.shadowMapsRendered, 6);
      // Where the worker pays: every other map of the frame's six, on llvmpipe only.
      EXPECT_EQ(two.shadowMapsInParallel, software ? 3 : 0);
      expectSameFrames(one, two);
    }
  }
}

// A frame with one map to draw, or only maps kept from the frame before, has nothing to share.
TEST(ParallelShadowMaps, OneMapOrReusedMapsStayInOneContext) {
  Renderer& renderer = test_support::sharedRenderer();
  const Scene scene = test_support::shadowStage();
  const ViewCamera camera = lookFrom(scene, {0.0f, 5.0f, 6.0f}, {0.0f, 0.5f, 0.0f}, 48, 32);
  StageTimes times;
  const std::vector<Light> all = rig(0.0f);
  renderer.render(scene, all, glm::vec3(0.03f), camera, {}, times);
  const Frame one = renderer.render(scene, {rig(0.3f)[0]}, glm::vec3(0.03f), camera, {}, times);
  EXPECT_EQ(one.shadowMapsRendered, 1);
  EXPECT_EQ(one.shadowMapsInParallel, 0);
  const std::vector<Light> points = {all[0], all[1], all[4]};
  renderer.render(scene, points, glm::vec3(0.03f), camera, {}, times);
  const Frame reused = renderer.render(scene, points, glm::vec3(0.03f), camera, {}, times);
  EXPECT_EQ(reused.shadowMapsReused, 3);
  EXPECT_EQ(reused.shadowMapsInParallel, 0);
}

}  // namespace parallel_shadow_maps_test
