// Meshes open by an ulp (a UV sphere's seam and pole, as three.js and other generators compute
// them) cast their shadows from welded copies that are closed solids, so that the shadow pass
// skips their back faces (renderer/passes/gpu_geometry.h, mesh_topology.h): the maps are those
// of the welded mesh itself, and the lighting pass still draws the mesh as it is.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <vector>

#include "renderer/passes/gpu_geometry.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/mesh_topology.h"
#include "renderer/view/cube_faces.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace welded_casters_test {

using namespace omnishadow;
using test_support::lookFrom;
using test_support::sharedRenderer;

namespace {

// A floor with `ball` floating over it, drawn once or as several instances.
Scene ballOverFloor(const builder::MeshData& ball, int instances) {
  Scene scene;
  Material grey;
  grey.baseColorFactor = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
  grey.roughnessFactor = 0.6f;
  scene.materials.push_back(grey);
  test::placeMesh(scene, builder::makePlane(8.0f, 4), glm::mat4(1.0f), 0);
  test::placeMesh(scene, ball, glm::translate(glm::mat4(1.0f), {-0.6f, 1.2f, 0.2f}), 0);
  const int mesh = static_cast<int>(scene.meshes.size()) - 1;
  for (int i = 1; i < instances; ++i) {
    const glm::mat4 world =
        glm::translate(glm::mat4(1.0f), {0.9f * static_cast<float>(i), 0.8f, -0.5f});
    scene.instances.push_back({mesh, world, -1, {}, {}});
    scene.bounds.extend(scene.meshes[static_cast<std::size_t>(mesh)].bounds.transformed(world));
  }
  return scene;
}

Frame renderWithMaps(const Scene& scene) {
  Light lamp;
  lamp.name = "lamp";
  lamp.position = {0.3f, 3.0f, 0.5f};
  lamp.intensity = 20.0f;
  lamp.shadow.resolution = 256;
  RenderSettings settings;
  settings.readShadowMaps = true;
  StageTimes times;
  const ViewCamera camera = lookFrom(scene, {0.0f, 4.0f, 5.0f}, {0.0f, 0.3f, 0.0f}, 96, 72);
  return sharedRenderer().render(scene, {lamp}, glm::vec3(0.02f), camera, settings, times);
}

}  // namespace

TEST(WeldedCasters, AnUlpOpenSphereIsClosedInTheCasterStreamOnly) {
  const builder::MeshData ball = test::ulpSeamSphere(0.5f, 32, 16);
  ASSERT_FALSE(isClosedSolid(ball.positions, ball.indices));  // the premise
  sharedRenderer();                                           // its GL context is current here
  for (const int instances : {1, 3}) {
    SCOPED_TRACE(instances);
    const GpuGeometry geometry(ballOverFloor(ball, instances));
    const GpuMeshRange& range = geometry.meshes()[1];
    EXPECT_FALSE(range.closed);
    EXPECT_TRUE(range.closedInStream);
    for (const GpuDraw& draw : geometry.draws())
      if (draw.mesh == 1) {
        EXPECT_GE(draw.casterFirstIndex, 0);
      }
    EXPECT_FALSE(geometry.meshes()[0].closedInStream);  // the floor is open
  }
}

// The shadow maps of the ulp-open sphere are, texel for texel, those of the sphere made from its
// welded positions, which is closed as it is: the shadow pass draws the welded copy and skips
// its back faces (drawn from the open positions, some texels would differ by their rounding).
TEST(WeldedCasters, ShadowMapsAreThoseOfTheWeldedMesh) {
  const builder::MeshData ball = test::ulpSeamSphere(0.5f, 32, 16);
  const std::optional<std::vector<glm::vec3>> welded =
      checkSolid(ball.positions, ball.indices).welded;
  ASSERT_TRUE(welded);
  builder::MeshData weldedBall = ball;
  weldedBall.positions = *welded;
  ASSERT_TRUE(isClosedSolid(weldedBall.positions, weldedBall.indices));
  for (const int instances : {1, 3}) {
    SCOPED_TRACE(instances);
    const Frame open = renderWithMaps(ballOverFloor(ball, instances));
    const Frame closed = renderWithMaps(ballOverFloor(weldedBall, instances));
    ASSERT_EQ(open.shadowMaps.size(), 1u);
    ASSERT_EQ(closed.shadowMaps.size(), 1u);
    for (int face = 0; face < kCubeFaceCount; ++face)
      EXPECT_EQ(open.shadowMaps[0].distances.faces[static_cast<std::size_t>(face)],
                closed.shadowMaps[0].distances.faces[static_cast<std::size_t>(face)])
          << "face " << face;
    // The ball's shadow is on the floor: straight down from the lamp (the -Y face's centre) the
    // floor is 3 m away, and towards the ball the ball is nearer.
    const CubeDistances& map = open.shadowMaps[0].distances;
    const int middle = map.resolution / 2;
    EXPECT_NEAR(map.at(CubeFace::NegY, middle, middle), 3.0f, 0.05f);
  }
}

}  // namespace welded_casters_test
