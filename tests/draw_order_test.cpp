// Blended surfaces compose nearer over farther, whatever order the scene lists them in.
#include "renderer/view/draw_order.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/render/renderer.h"
#include "renderer/view/camera.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace draw_order_test {

using namespace omnishadow;

namespace {

glm::mat4 viewFrom(const glm::vec3& eye, const glm::vec3& target) {
  return glm::lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f));
}

// Two unlit, half-transparent panes facing a camera on +Z: red at z = `redZ`, blue at
// `blueZ`, listed red first.
Scene twoPanes(float redZ, float blueZ) {
  Scene scene;
  Material red, blue;
  red.baseColorFactor = {1.0f, 0.0f, 0.0f, 0.5f};
  blue.baseColorFactor = {0.0f, 0.0f, 1.0f, 0.5f};
  for (Material* m : {&red, &blue}) {
    m->alphaMode = AlphaMode::Blend;
    m->doubleSided = true;
    m->unlit = true;
  }
  scene.materials = {red, blue};
  const glm::mat4 faceCamera =
      glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1.0f, 0.0f, 0.0f));
  test::placeMesh(scene, builder::makePlane(2.0f),
                  glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, redZ}) * faceCamera, 0);
  test::placeMesh(scene, builder::makePlane(2.0f),
                  glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, blueZ}) * faceCamera, 1);
  return scene;
}

// The linear, premultiplied RGBA at the middle of the frame of `scene` seen from z = 4.
glm::vec4 middlePixel(const Scene& scene) {
  StageTimes times;
  const Frame frame = test_support::sharedRenderer().render(
      scene, {}, glm::vec3(0.0f),
      test_support::lookFrom(scene, {0.0f, 0.0f, 4.0f}, glm::vec3(0.0f), 32, 24, 30.0f),
      RenderSettings{}, times);
  const FloatImage& beauty = frame.beauty;
  const int x = beauty.width / 2, y = beauty.height / 2;
  return {beauty.at(x, y, 0), beauty.at(x, y, 1), beauty.at(x, y, 2), beauty.at(x, y, 3)};
}

// One double-sided, half-transparent, unlit mesh of two unit squares facing a camera on +Z:
// a red one at z = 0.5 listed first and a blue one at z = -0.5, each with its normal outward
// (the front and back of a thin box).
Scene frontAndBackSquares() {
  Scene scene;
  Material glass;
  glass.baseColorFactor = {1.0f, 1.0f, 1.0f, 0.5f};
  glass.alphaMode = AlphaMode::Blend;
  glass.doubleSided = true;
  glass.unlit = true;
  scene.materials = {glass};
  builder::MeshData squares;
  squares.positions = {{-1, -1, 0.5f},  {1, -1, 0.5f},  {1, 1, 0.5f},  {-1, 1, 0.5f},
                       {-1, -1, -0.5f}, {-1, 1, -0.5f}, {1, 1, -0.5f}, {1, -1, -0.5f}};
  squares.normals = {{0, 0, 1},  {0, 0, 1},  {0, 0, 1},  {0, 0, 1},
                     {0, 0, -1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
  squares.uvs.assign(8, glm::vec2(0.0f));
  squares.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  test::placeMesh(scene, squares, glm::mat4(1.0f), 0);
  const glm::vec4 red(1, 0, 0, 1), blue(0, 0, 1, 1);
  scene.meshes[0].colors = {red, red, red, red, blue, blue, blue, blue};
  return scene;
}

}  // namespace

TEST(BlendedOrder, FarthestFirstAlongTheViewAxis) {
  const glm::mat4 view = viewFrom({0.0f, 0.0f, 10.0f}, glm::vec3(0.0f));
  // Depths 10, 12, 8 and 9.5 (the last one off the axis: depth, not distance, counts).
  const std::vector<DrawCenter> draws = {{0, {0.0f, 0.0f, 0.0f}},
                                         {1, {0.0f, 0.0f, -2.0f}},
                                         {2, {0.0f, 0.0f, 2.0f}},
                                         {3, {6.0f, 0.0f, 0.5f}}};
  EXPECT_EQ(farthestFirst(draws, view), (std::vector<std::size_t>{1, 0, 3, 2}));
  // Seen from the other side, the other way round.
  EXPECT_EQ(farthestFirst(draws, viewFrom({0.0f, 0.0f, -10.0f}, glm::vec3(0.0f))),
            (std::vector<std::size_t>{2, 3, 0, 1}));
}

TEST(BlendedOrder, EqualDepthsKeepTheSceneOrder) {
  const glm::mat4 view = viewFrom({0.0f, 0.0f, 10.0f}, glm::vec3(0.0f));
  const std::vector<DrawCenter> draws = {{7, {1.0f, 0.0f, 0.0f}},
                                         {3, {-1.0f, 0.0f, 0.0f}},
                                         {5, {0.0f, 2.0f, 0.0f}},
                                         {9, {0.0f, 0.0f, -1.0f}}};
  EXPECT_EQ(farthestFirst(draws, view), (std::vector<std::size_t>{9, 7, 3, 5}));
  EXPECT_TRUE(farthestFirst({}, view).empty());
}

// Opaque surfaces: nearest first by the far side of each bounding sphere, equal depths in the
// scene's order. A floor whose centre lies nearer than a box standing on it, but whose sphere
// reaches farther, goes after the box.
TEST(DrawOrder, NearestFirstByTheFarSideOfEachSphere) {
  const glm::mat4 view = viewFrom({0.0f, 0.0f, 10.0f}, glm::vec3(0.0f));
  // Far sides at depths 10, 12, 8, 9.5 and 10.
  const std::vector<DrawCenter> draws = {{0, {0.0f, 0.0f, 0.0f}},
                                         {1, {0.0f, 0.0f, -2.0f}},
                                         {2, {0.0f, 0.0f, 2.0f}},
                                         {3, {6.0f, 0.0f, 0.5f}},
                                         {4, {0.0f, 3.0f, 0.0f}}};
  EXPECT_EQ(nearestFirst(draws, view), (std::vector<std::size_t>{2, 3, 0, 4, 1}));
  EXPECT_TRUE(nearestFirst({}, view).empty());
  // The floor's centre at depth 9, the box's at 9.5; the floor reaches to 14, the box to 10.
  const std::vector<DrawCenter> floorAndBox = {{0, {0.0f, -1.0f, 1.0f}, 5.0f},
                                               {1, {0.0f, 0.0f, 0.5f}, 0.5f}};
  EXPECT_EQ(nearestFirst(floorAndBox, view), (std::vector<std::size_t>{1, 0}));
}

// Red over blue over the black background where red is nearer, and blue over red where blue
// is: "over" in the order the panes lie, not the order the scene lists them.
TEST(BlendedOrder, NearerPaneComposesOverTheFartherOneInEitherSceneOrder) {
  const glm::vec4 redNearer = middlePixel(twoPanes(1.0f, 0.0f));
  EXPECT_NEAR(redNearer.r, 0.5f, 1e-5f);
  EXPECT_NEAR(redNearer.g, 0.0f, 1e-5f);
  EXPECT_NEAR(redNearer.b, 0.25f, 1e-5f);
  EXPECT_NEAR(redNearer.a, 0.75f, 1e-5f);
  const glm::vec4 blueNearer = middlePixel(twoPanes(0.0f, 1.0f));
  EXPECT_NEAR(blueNearer.r, 0.25f, 1e-5f);
  EXPECT_NEAR(blueNearer.b, 0.5f, 1e-5f);
  EXPECT_NEAR(blueNearer.a, 0.75f, 1e-5f);
}

// A double-sided blended mesh draws its back faces, then its front faces: the red front square
// over the blue back one, though the mesh lists the front one first.
TEST(BlendedOrder, DoubleSidedBlendedMeshComposesItsFrontOverItsBack) {
  const glm::vec4 pixel = middlePixel(frontAndBackSquares());
  EXPECT_NEAR(pixel.r, 0.5f, 1e-5f);
  EXPECT_NEAR(pixel.g, 0.0f, 1e-5f);
  EXPECT_NEAR(pixel.b, 0.25f, 1e-5f);
  EXPECT_NEAR(pixel.a, 0.75f, 1e-5f);
}

}  // namespace draw_order_test
