// The beauty's facing-light loop (LightingFeatures::facingLightLoop, FACING_LIGHT_LOOP in
// shaders/lighting.frag): each lane group of the lighting pass visits only the lights that some
// of its pixels may face. The AOV pass still visits every light, so its beauty is the
// reference: both must agree on a rig whose lights each face away from part of the frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "renderer/passes/lighting_pass.h"
#include "renderer/render/renderer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::facing_light_loop_test {
namespace {

using test_support::lookFrom;
using test_support::sharedRenderer;

int addMaterial(Scene& scene, glm::vec4 color, float metallic, float roughness) {
  Material m;
  m.baseColorFactor = color;
  m.metallicFactor = metallic;
  m.roughnessFactor = roughness;
  scene.materials.push_back(m);
  return static_cast<int>(scene.materials.size()) - 1;
}

// A floor, a smooth sphere (its shading normals differ from its faces' near the terminators)
// and a box.
Scene roundScene() {
  Scene scene;
  test::placeMesh(scene, builder::makePlane(8.0f, 4), glm::mat4(1.0f),
                  addMaterial(scene, {0.8f, 0.75f, 0.7f, 1.0f}, 0.0f, 0.7f));
  test::placeMesh(scene, builder::makeSphere(0.8f, 24, 12),
                  glm::translate(glm::mat4(1.0f), {0.4f, 0.9f, 0.0f}),
                  addMaterial(scene, {0.6f, 0.7f, 0.9f, 1.0f}, 0.3f, 0.35f));
  test::placeMesh(scene, builder::makeBox({0.4f, 0.6f, 0.4f}),
                  glm::translate(glm::mat4(1.0f), {-1.2f, 0.6f, 0.5f}),
                  addMaterial(scene, {0.9f, 0.3f, 0.2f, 1.0f}, 0.0f, 0.5f));
  return scene;
}

Light light(const std::string& name, LightType type, glm::vec3 position, glm::vec3 direction,
            float intensity) {
  Light l;
  l.name = name;
  l.type = type;
  l.position = position;
  l.direction = glm::normalize(direction);
  l.intensity = intensity;
  l.outerConeAngle = 0.9f;
  l.shadow.resolution = 128;
  l.shadow.filter = ShadowFilter::Pcf;
  return l;
}

// Lights on every side: the sphere's lane groups face some of them and not others, and the one
// under the floor faces away from everything the camera sees.
std::vector<Light> surroundingLights() {
  return {light("above", LightType::Point, {0.5f, 3.0f, 1.0f}, {0, -1, 0}, 15.0f),
          light("low left", LightType::Point, {-2.5f, 0.4f, 0.5f}, {0, -1, 0}, 6.0f),
          light("right", LightType::Spot, {3.0f, 1.0f, 0.5f}, {-1.0f, -0.1f, 0.0f}, 20.0f),
          light("grazing", LightType::Directional, {0, 0, 0}, {-1.0f, -0.15f, -0.4f}, 1.2f),
          light("under", LightType::Point, {0.0f, -1.0f, 0.0f}, {0, -1, 0}, 10.0f)};
}

Frame render(const Scene& scene, const std::vector<Light>& lights, const RenderSettings& settings) {
  const ViewCamera camera = lookFrom(scene, {0.5f, 2.5f, 4.5f}, {0.0f, 0.6f, 0.0f}, 128, 96);
  StageTimes times;
  return sharedRenderer().render(scene, lights, glm::vec3(0.02f), camera, settings, times);
}

TEST(FacingLightLoop, TheBeautyEqualsTheAovPassThatVisitsEveryLight) {
  const Scene scene = roundScene();
  const std::vector<Light> lights = surroundingLights();
  for (Shading shading : {Shading::Pbr, Shading::Phong}) {
    SCOPED_TRACE(shading == Shading::Pbr ? "pbr" : "phong");
    RenderSettings settings{.shading = shading};
    const Frame beauty = render(scene, lights, settings);
    settings.aovs = true;
    const Frame reference = render(scene, lights, settings);
    ASSERT_EQ(beauty.beauty.pixels.size(), reference.beauty.pixels.size());
    float brightest = 0.0f, largest = 0.0f;
    for (std::size_t i = 0; i < beauty.beauty.pixels.size(); ++i) {
      brightest = std::max(brightest, reference.beauty.pixels[i]);
      largest = std::max(largest, std::abs(beauty.beauty.pixels[i] - reference.beauty.pixels[i]));
    }
    ASSERT_GT(brightest, 0.1f);
    // The two passes are different shader variants, so allow float rounding and no more: a
    // light left out where it faces a pixel moves that pixel by its whole contribution.
    EXPECT_LE(largest, 1e-6f * brightest);
  }
}

// The rig above is a fair test only if each light faces away from part of the picture and
// towards another part: each one alone leaves some pixels dark, and each but the one under the
// floor lights some.
TEST(FacingLightLoop, EachLightOfTheRigLightsOnlyPartOfThePicture) {
  const Scene scene = roundScene();
  const Frame ambient = render(scene, {}, {});
  for (const Light& l : surroundingLights()) {
    SCOPED_TRACE(l.name);
    const Frame frame = render(scene, {l}, {});
    std::size_t lit = 0, unlit = 0;
    for (std::size_t i = 0; i < frame.beauty.pixels.size(); i += 4) {
      if (ambient.beauty.pixels[i + 3] == 0.0f) continue;  // background
      const bool brighter = frame.beauty.pixels[i] > ambient.beauty.pixels[i] + 1e-4f;
      (brighter ? lit : unlit) += 1;
    }
    EXPECT_GT(unlit, 200u);
    if (l.name != "under") {
      EXPECT_GT(lit, 500u);
    }
  }
}

TEST(FacingLightLoop, OnlyForFramesWhoseLightsFitItsMaskAndHaveNoRange) {
  std::vector<Light> lights(kMaxFacingLoopLights, light("l", LightType::Point, {}, {0, -1, 0}, 1));
  EXPECT_TRUE(lightingFeatures(lights, DebugView::None).facingLightLoop);
  lights.push_back(lights.back());
  EXPECT_FALSE(lightingFeatures(lights, DebugView::None).facingLightLoop);
  lights.resize(2);
  lights[1].range = 5.0f;  // lights with a range loop over their clusters instead
  EXPECT_FALSE(lightingFeatures(lights, DebugView::None).facingLightLoop);
}

}  // namespace
}  // namespace omnishadow::facing_light_loop_test
