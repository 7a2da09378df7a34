// Draws of one mesh and material at one transform, bit for bit (GpuDraw::repeatedLater and
// repeatsEarlier): the passes where a copy adds nothing draw one of them, and every output is
// that of the scene drawn copy by copy.
#include <gtest/gtest.h>

#include <cstddef>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "renderer/passes/gpu_geometry.h"
#include "renderer/render/renderer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/same_frame.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::repeated_draws_test {
namespace {

using test_support::expectSameFrame;
using test_support::lookFrom;
using test_support::sharedRenderer;

GpuDraw drawOf(int mesh, int material, const glm::mat4& world) {
  GpuDraw draw;
  draw.mesh = mesh;
  draw.material = material;
  draw.world = world;
  return draw;
}

TEST(RepeatedDraws, CopiesAreMarkedFromTheFirstToTheLastInSceneOrder) {
  const glm::mat4 there = glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 2.0f, 3.0f));
  std::vector<GpuDraw> draws = {drawOf(0, 0, there), drawOf(1, 0, there), drawOf(0, 0, there),
                                drawOf(0, 1, there), drawOf(0, 0, there)};
  markRepeatedDraws(draws);
  const bool later[] = {true, false, true, false, false};
  const bool earlier[] = {false, false, true, false, true};
  for (std::size_t i = 0; i < draws.size(); ++i) {
    EXPECT_EQ(draws[i].repeatedLater, later[i]) << i;
    EXPECT_EQ(draws[i].repeatsEarlier, earlier[i]) << i;
  }
}

// The same numbers are not the same bits: a transform with -0 where the other has +0, or one
// ulp apart, is another draw (its vertices may round otherwise).
TEST(RepeatedDraws, TransformsThatDifferInAnyBitAreNotCopies) {
  glm::mat4 negativeZero(1.0f);
  negativeZero[1][0] = -0.0f;
  glm::mat4 ulp(1.0f);
  ulp[3][0] = std::nextafter(0.0f, 1.0f);
  std::vector<GpuDraw> draws = {drawOf(0, 0, glm::mat4(1.0f)), drawOf(0, 0, negativeZero),
                                drawOf(0, 0, ulp)};
  markRepeatedDraws(draws);
  for (const GpuDraw& draw : draws) {
    EXPECT_FALSE(draw.repeatedLater);
    EXPECT_FALSE(draw.repeatsEarlier);
  }
}

// A floor, an opaque box three times over, an alpha-tested pane twice over and a blended pane
// twice over, each copy at the same transform, under a point light with translucent shadows.
// With `ownMeshes`, every copy has a mesh of its own with the same data: nothing is a repeated
// draw, and each copy is drawn in every pass.
Scene copies(bool ownMeshes, bool blended) {
  Scene scene;
  Material floor;
  floor.baseColorFactor = {0.8f, 0.8f, 0.8f, 1.0f};
  Material box = floor;
  box.baseColorFactor = {0.9f, 0.3f, 0.2f, 1.0f};
  Material cutOut = floor;
  cutOut.baseColorFactor = {0.2f, 0.7f, 0.3f, 1.0f};
  cutOut.alphaMode = AlphaMode::Mask;
  cutOut.doubleSided = true;
  Material glass = floor;
  glass.baseColorFactor = {0.2f, 0.4f, 0.9f, 0.5f};
  glass.alphaMode = AlphaMode::Blend;
  glass.doubleSided = true;
  scene.materials = {floor, box, cutOut, glass};
  test::placeMesh(scene, builder::makePlane(6.0f), glm::mat4(1.0f), 0);
  const auto copiesOf = [&](const builder::MeshData& mesh, const glm::mat4& world, int material,
                            int count) {
    test::placeMesh(scene, mesh, world, material);
    const MeshInstance first = scene.instances.back();
    for (int i = 1; i < count; ++i) {
      if (ownMeshes) {
        test::placeMesh(scene, mesh, world, material);
      } else {
        scene.instances.push_back(first);
      }
    }
  };
  copiesOf(builder::makeBox(glm::vec3(0.4f)), glm::translate(glm::mat4(1.0f), {-0.8f, 0.4f, 0.0f}),
           1, 3);
  copiesOf(builder::makePlane(0.8f), glm::translate(glm::mat4(1.0f), {0.8f, 0.9f, -0.3f}), 2, 2);
  if (blended)
    copiesOf(builder::makePlane(0.9f), glm::translate(glm::mat4(1.0f), {0.3f, 1.4f, 0.9f}), 3, 2);
  return scene;
}

std::vector<Light> pointLight() {
  Light light;
  light.name = "point";
  light.position = {0.2f, 3.5f, 0.4f};
  light.intensity = 30.0f;
  light.shadow.resolution = 256;
  light.shadow.translucent = true;
  return {light};
}

Frame render(const Scene& scene, const RenderSettings& settings) {
  const ViewCamera camera = lookFrom(scene, {0.0f, 3.0f, 3.5f}, {0.0f, 0.3f, 0.0f}, 160, 120);
  StageTimes times;
  return sharedRenderer().render(scene, pointLight(), glm::vec3(0.05f), camera, settings, times);
}

struct Case {
  std::string name;
  bool blended;
  RenderSettings settings;
};

std::vector<Case> cases() {
  RenderSettings srgb8;
  srgb8.srgb8Exposure = 0.0f;
  RenderSettings aovs;
  aovs.aovs = true;
  aovs.layers.albedo = aovs.layers.objectId = aovs.layers.materialId = true;
  RenderSettings ids;
  ids.objectIds = true;
  return {{"8-bit beauty", false, srgb8},
          {"float beauty, blended copies", true, srgb8},
          {"AOVs with ids", true, aovs},
          {"object ids", true, ids}};
}

// Every output byte for byte: the ids too, which fails when a set keeps a copy that does not
// win the depth test among them (the last opaque one, the first alpha-tested one); the beauty
// fails when blended copies, or the translucent shadow of each, are drawn once.
TEST(RepeatedDraws, EveryOutputIsThatOfTheCopiesDrawnOneByOne) {
  for (const Case& c : cases()) {
    const Frame repeated = render(copies(false, c.blended), c.settings);
    const Frame drawnEach = render(copies(true, c.blended), c.settings);
    expectSameFrame(repeated, drawnEach, c.name);
  }
}

// Which copy's id a pixel holds: the last of the opaque box's three (instances 1 to 3), the
// first of the cut-out pane's two (instances 4 and 5), as with every copy drawn.
TEST(RepeatedDraws, EachPixelHoldsTheIdOfTheCopyThatWinsTheDepthTest) {
  RenderSettings settings;
  settings.objectIds = true;
  const Scene scene = copies(false, false);
  const Frame frame = render(scene, settings);
  ASSERT_TRUE(frame.objectIds);
  const FloatImage& ids = *frame.objectIds;
  int box = 0, pane = 0;
  for (int y = 0; y < ids.height; ++y)
    for (int x = 0; x < ids.width; ++x) {
      const float id = ids.at(x, y, 0);
      EXPECT_TRUE(id == -1.0f || id == 0.0f || id == 3.0f || id == 4.0f) << id;
      box += id == 3.0f;
      pane += id == 4.0f;
    }
  EXPECT_GT(box, 200);
  EXPECT_GT(pane, 100);
}

}  // namespace
}  // namespace omnishadow::repeated_draws_test
