#include "renderer/scene/scene_fingerprint.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <set>
#include <string>

#include "scenes/builder/gltf_builder.h"

namespace omnishadow {
namespace {

// Two spheres of ~1k triangles each, placed by two instances: positions and indices long
// enough for the hash's 32-byte blocks, with tails of every length.
Scene twoSpheres() {
  Scene scene;
  for (int k = 0; k < 2; ++k) {
    const builder::MeshData data = builder::makeSphere(1.0f + 0.5f * k, 23 + k, 12);
    Mesh mesh;
    mesh.name = "sphere" + std::to_string(k);
    mesh.positions = data.positions;
    mesh.normals = data.normals;
    mesh.indices = data.indices;
    scene.meshes.push_back(mesh);
    MeshInstance instance;
    instance.mesh = k;
    instance.world[3] = glm::vec4(3.0f * k, 0.0f, 0.0f, 1.0f);
    scene.instances.push_back(instance);
  }
  return scene;
}

void flipBit(float& f, int bit) {
  std::uint32_t b = 0;
  std::memcpy(&b, &f, sizeof b);
  b ^= 1u << bit;
  std::memcpy(&f, &b, sizeof b);
}

TEST(ShadowFingerprint, EqualScenesHashEqualAndNormalsDoNotCount) {
  Scene a = twoSpheres();
  const Scene b = twoSpheres();
  EXPECT_EQ(shadowFingerprint(a), shadowFingerprint(b));
  for (glm::vec3& n : a.meshes[0].normals) n = -n;  // shading only: the same shadows
  a.meshes[1].name = "renamed";
  EXPECT_EQ(shadowFingerprint(a), shadowFingerprint(b));
}

// Every position of both meshes, every bit of one coordinate: each one-bit change gives a
// value of its own (a hash that dropped a lane, a block or a tail would repeat values).
TEST(ShadowFingerprint, EveryBitOfEveryPositionCounts) {
  const Scene original = twoSpheres();
  std::set<std::uint64_t> seen{shadowFingerprint(original)};
  std::size_t changes = 0;
  for (std::size_t m = 0; m < original.meshes.size(); ++m) {
    for (std::size_t v = 0; v < original.meshes[m].positions.size(); ++v) {
      Scene changed = original;
      flipBit(changed.meshes[m].positions[v][static_cast<int>(v % 3)], static_cast<int>(v % 32));
      seen.insert(shadowFingerprint(changed));
      ++changes;
    }
  }
  EXPECT_EQ(seen.size(), changes + 1);
  for (int bit = 0; bit < 32; ++bit) {
    Scene changed = original;
    flipBit(changed.meshes[1].positions.back().z, bit);
    EXPECT_NE(shadowFingerprint(changed), shadowFingerprint(original)) << "bit " << bit;
  }
}

TEST(ShadowFingerprint, IndicesInstancesAndArrayBoundariesCount) {
  const Scene original = twoSpheres();
  const std::uint64_t h = shadowFingerprint(original);

  Scene swapped = original;  // the same triangles, another winding: other back faces
  std::swap(swapped.meshes[0].indices[1], swapped.meshes[0].indices[2]);
  EXPECT_NE(shadowFingerprint(swapped), h);

  Scene moved = original;
  flipBit(moved.instances[1].world[3][1], 0);
  EXPECT_NE(shadowFingerprint(moved), h);

  Scene dropped = original;  // one triangle fewer
  dropped.meshes[1].indices.resize(dropped.meshes[1].indices.size() - 3);
  EXPECT_NE(shadowFingerprint(dropped), h);

  // A vertex moved from the end of one mesh to the start of the next: the same bytes in a row,
  // split differently.
  Scene shifted = original;
  shifted.meshes[1].positions.insert(shifted.meshes[1].positions.begin(),
                                     shifted.meshes[0].positions.back());
  shifted.meshes[0].positions.pop_back();
  EXPECT_NE(shadowFingerprint(shifted), h);

  Scene zero = original;  // a zero word appended is not nothing
  zero.meshes[0].indices.push_back(0);
  EXPECT_NE(shadowFingerprint(zero), h);
}

}  // namespace
}  // namespace omnishadow
