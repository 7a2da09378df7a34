// The AOV contract where blended surfaces are seen (issue 18): every pixel with coverage has a
// finite position, a unit normal and a camera distance. Where no opaque surface is behind them
// the channels describe the front-most blended surface.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/view/camera.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"

namespace blended_aovs_test {

using namespace omnishadow;

namespace {

Renderer& contextForThisProgram() {
  static Renderer renderer(ContextOptions{});
  return renderer;
}

Frame aovsOf(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera) {
  RenderSettings settings;
  settings.aovs = true;
  settings.layers.objectId = true;
  StageTimes times;
  return contextForThisProgram().render(scene, lights, glm::vec3(0.03f), camera, settings, times);
}

struct ContractCounts {
  int covered = 0, broken = 0;
};

ContractCounts checkContract(const FloatImage& aovs) {
  ContractCounts counts;
  const int a = aovs.channelIndex("A"), p = aovs.channelIndex("P.X"), n = aovs.channelIndex("N.X");
  const int z = aovs.channelIndex("Z"), id = aovs.channelIndex("objectId");
  for (int y = 0; y < aovs.height; ++y)
    for (int x = 0; x < aovs.width; ++x) {
      if (!(aovs.at(x, y, a) > 0.0f)) continue;
      ++counts.covered;
      const glm::vec3 P{aovs.at(x, y, p), aovs.at(x, y, p + 1), aovs.at(x, y, p + 2)};
      const glm::vec3 N{aovs.at(x, y, n), aovs.at(x, y, n + 1), aovs.at(x, y, n + 2)};
      const bool ok = std::isfinite(P.x) && std::isfinite(P.y) && std::isfinite(P.z) &&
                      std::abs(glm::length(N) - 1.0f) < 1e-3f && aovs.at(x, y, z) > 0.0f &&
                      std::isfinite(aovs.at(x, y, z)) && aovs.at(x, y, id) >= 0.0f;
      counts.broken += !ok;
    }
  return counts;
}

}  // namespace

// A half-transparent pane in front of nothing and, beside it, in front of an opaque box: the
// pane alone gives the pane's P/N; over the box the box's.
TEST(BlendedAovs, PaneOverBackgroundDescribesThePaneAndOverABoxTheBox) {
  Scene scene;
  Material glass;
  glass.baseColorFactor = {0.2f, 0.5f, 0.9f, 0.4f};
  glass.alphaMode = AlphaMode::Blend;
  glass.doubleSided = true;
  scene.materials = {glass, Material{}};
  auto add = [&](const builder::MeshData& d, const glm::mat4& world, int material) {
    test::placeMesh(scene, d, world, material);
  };
  // The pane: the XZ plane turned to face +Z, at z = 0; the box behind its right half.
  add(builder::makePlane(2.0f),
      glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1.0f, 0.0f, 0.0f)), 0);
  add(builder::makeBox({0.4f, 0.4f, 0.4f}), glm::translate(glm::mat4(1.0f), {0.5f, 0.0f, -1.0f}),
      1);
  Light lamp;
  lamp.name = "lamp";
  lamp.position = {0.0f, 1.0f, 3.0f};
  CameraRequest request;
  request.eye = glm::vec3(0.0f, 0.0f, 4.0f);
  request.target = glm::vec3(0.0f);
  request.fovDegrees = 40.0f;
  request.width = 96;
  request.height = 64;
  const ViewCamera camera = resolveCamera(scene, request);
  const Frame frame = aovsOf(scene, {lamp}, camera);
  const FloatImage& aovs = *frame.aovs;
  const ContractCounts counts = checkContract(aovs);
  EXPECT_GT(counts.covered, 1000);
  EXPECT_EQ(counts.broken, 0);

  // Left of the box: only the pane, at z = 0, facing the camera, object 0.
  const int p = aovs.channelIndex("P.X"), n = aovs.channelIndex("N.X");
  const int id = aovs.channelIndex("objectId");
  const int left = aovs.width * 3 / 8, right = aovs.width * 5 / 8, row = aovs.height / 2;
  EXPECT_NEAR(aovs.at(left, row, p + 2), 0.0f, 1e-4f);
  EXPECT_NEAR(aovs.at(left, row, n + 2), 1.0f, 1e-3f);
  EXPECT_EQ(aovs.at(left, row, id), 0.0f);
  // Over the box: the box's front face at z = -0.6, object 1.
  EXPECT_NEAR(aovs.at(right, row, p + 2), -0.6f, 1e-4f);
  EXPECT_EQ(aovs.at(right, row, id), 1.0f);
}

// The Sundial: 4,678 pixels of its AOVs had coverage but no P or N.
TEST(BlendedAovs, SundialHasNoCoveredPixelWithoutPositionOrNormal) {
  const Scene scene = loadGltf(OMNISHADOW_SOURCE_DIR "/scenes/thirdparty/Sundial/Sundial.glb");
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, -0.4f));
  CameraRequest request;
  request.width = 160;
  request.height = 120;
  const Frame frame = aovsOf(scene, {sun}, resolveCamera(scene, request));
  const ContractCounts counts = checkContract(*frame.aovs);
  EXPECT_GT(counts.covered, 2000);
  EXPECT_EQ(counts.broken, 0);
}

}  // namespace blended_aovs_test
