// The scene geometry kept from one render to the next (renderer/passes/gpu_geometry.h): found
// again for the same meshes and instances, made anew for changed ones, also when the change
// is made in place to the scene object that was rendered before (as posing an animated scene
// for the next frame does).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "renderer/passes/gpu_geometry.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::geometry_cache_test {
namespace {

Scene boxTextured() {
  return loadGltf(std::string(OMNISHADOW_SOURCE_DIR) +
                  "/scenes/thirdparty/BoxTextured/BoxTextured.glb");
}

void moveMeshes(Scene& scene, glm::vec3 by) {
  for (Mesh& mesh : scene.meshes) {
    for (glm::vec3& p : mesh.positions) p += by;
    mesh.bounds.min += by;
    mesh.bounds.max += by;
  }
}

TEST(GeometryCache, FindsTheLastGeometryForTheSameMeshesOnly) {
  test_support::sharedRenderer();  // its GL context is current here
  GeometryCache cache;
  Scene scene = boxTextured();
  const std::shared_ptr<const GpuGeometry> first = cache.find(scene, meshDigests(scene));
  ASSERT_TRUE(first);
  EXPECT_EQ(cache.find(scene, meshDigests(scene)), first);
  const Scene copy = scene;  // another object with the same contents
  EXPECT_EQ(cache.find(copy, meshDigests(copy)), first);
  EXPECT_EQ(first->draws().size(), scene.instances.size());

  Scene materials = scene;  // materials and images are not geometry
  materials.materials[0].baseColorFactor = glm::vec4(0.25f);
  for (std::uint8_t& v : materials.images[0].rgba) v = 0;
  EXPECT_EQ(cache.find(materials, meshDigests(materials)), first);

  moveMeshes(scene, {0.5f, 0.0f, 0.0f});  // in place
  const std::shared_ptr<const GpuGeometry> moved = cache.find(scene, meshDigests(scene));
  EXPECT_NE(moved, first);
  EXPECT_EQ(cache.find(scene, meshDigests(scene)), moved);
  EXPECT_NE(cache.find(copy, meshDigests(copy)),
            moved);  // only the last is kept: the first is made again
}

// Rendering one scene object, changing its meshes in place, and rendering it again draws the
// change, the same picture as a render of a separate scene with the same change; changed back
// it draws the first picture again.
TEST(GeometryCache, AMeshChangedInPlaceBetweenRendersDrawsTheChange) {
  Scene scene = boxTextured();
  Scene moved = scene;
  moveMeshes(moved, {0.3f, -0.2f, 0.0f});
  Light light;
  light.name = "key";
  light.position = {1.5f, 2.0f, 2.0f};
  light.intensity = 8.0f;
  const ViewCamera camera = test_support::lookFrom(scene, {1.6f, 1.2f, 2.2f}, {0, 0, 0}, 64, 48);
  const auto draw = [&](const Scene& s) {
    return test_support::renderSrgb8(s, {light}, camera, glm::vec3(0.05f));
  };
  const std::vector<std::uint8_t> first = draw(scene);
  EXPECT_EQ(draw(scene), first);
  const std::vector<std::uint8_t> expected = draw(moved);
  ASSERT_NE(expected, first);
  EXPECT_EQ(draw(scene), first);
  moveMeshes(scene, {0.3f, -0.2f, 0.0f});
  EXPECT_EQ(draw(scene), expected);
  moveMeshes(scene, {-0.3f, 0.2f, 0.0f});
  scene.meshes = boxTextured().meshes;  // exactly the first meshes again
  EXPECT_EQ(draw(scene), first);
}

}  // namespace
}  // namespace omnishadow::geometry_cache_test
