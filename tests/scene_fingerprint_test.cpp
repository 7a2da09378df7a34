#include "renderer/scene/scene_fingerprint.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scenes/builder/gltf_builder.h"

namespace omnishadow::scene_fingerprint_test {
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

// The geometry's hash: every array of every mesh counts (the GPU vertex holds them all), and
// so do line and point indices, each mesh's material index and bounds, the instances and the
// number of materials (the default material's index); materials' contents and images do not.
// A cut-out caster's texture shapes its shadow: its pixels count, and an image's hash kept
// from an earlier fingerprint (as a renderer keeps them for one Scene::revision) is taken
// without hashing the pixels again. An opaque caster's texture is not hashed at all.
TEST(ShadowFingerprint, ACutOutCastersPixelsCountAndTheirKeptHashIsTaken) {
  Scene scene = twoSpheres();
  scene.meshes[0].uv0.assign(scene.meshes[0].positions.size(), glm::vec2(0.5f));
  Image image;
  image.width = image.height = 4;
  image.rgba.assign(4 * 4 * 4, 200);
  scene.images.push_back(image);
  scene.textures.push_back(Texture{0, {}});
  Material cutOut;
  cutOut.alphaMode = AlphaMode::Mask;
  cutOut.baseColorTexture.texture = 0;
  scene.materials.push_back(cutOut);
  scene.meshes[0].material = 0;
  const std::vector<MeshDigests> meshes = meshDigests(scene);

  const std::uint64_t before = shadowFingerprint(scene);
  ImageHashes kept(scene.images.size());
  EXPECT_EQ(shadowFingerprint(scene, meshes, &kept), before);
  ASSERT_TRUE(kept[0].has_value());
  scene.images[0].rgba[7] = 0;  // one texel's alpha
  const std::uint64_t after = shadowFingerprint(scene);
  EXPECT_NE(after, before);
  EXPECT_EQ(shadowFingerprint(scene, meshes, &kept), before);  // the kept hash, as promised
  ImageHashes fresh(scene.images.size());
  EXPECT_EQ(shadowFingerprint(scene, meshes, &fresh), after);

  scene.materials[0].alphaMode = AlphaMode::Opaque;
  ImageHashes opaque(scene.images.size());
  shadowFingerprint(scene, meshes, &opaque);
  EXPECT_FALSE(opaque[0].has_value());
  EXPECT_EQ(shadowFingerprint(scene), shadowFingerprint(scene, meshes, &kept));
}

TEST(GeometryFingerprint, EveryMeshArrayCountsButNotMaterialsOrImages) {
  Scene original = twoSpheres();
  original.meshes[0].uv0.assign(original.meshes[0].positions.size(), glm::vec2(0.25f));
  original.meshes[0].uv1.assign(original.meshes[0].positions.size(), glm::vec2(0.5f));
  original.meshes[0].tangents.assign(original.meshes[0].positions.size(), glm::vec4(1, 0, 0, 1));
  original.meshes[0].colors.assign(original.meshes[0].positions.size(), glm::vec4(1.0f));
  original.meshes[1].lineIndices = {0, 1};
  original.meshes[1].pointIndices = {2};
  original.materials.resize(2);
  original.images.push_back({"image", 2, 2, std::vector<std::uint8_t>(16, 9), ""});
  const std::uint64_t h = geometryFingerprint(original);
  EXPECT_EQ(geometryFingerprint(Scene(original)), h);

  std::set<std::uint64_t> seen{h};
  const auto differs = [&](const char* what, void (*change)(Scene&)) {
    Scene changed = original;
    change(changed);
    const std::uint64_t value = geometryFingerprint(changed);
    EXPECT_NE(value, h) << what;
    seen.insert(value);
  };
  differs("normal", [](Scene& s) { flipBit(s.meshes[1].normals[7].y, 3); });
  differs("tangent", [](Scene& s) { flipBit(s.meshes[0].tangents[5].w, 31); });
  differs("uv0", [](Scene& s) { flipBit(s.meshes[0].uv0[9].x, 0); });
  differs("uv1", [](Scene& s) { flipBit(s.meshes[0].uv1[9].y, 0); });
  differs("color", [](Scene& s) { flipBit(s.meshes[0].colors.back().a, 20); });
  differs("position", [](Scene& s) { flipBit(s.meshes[0].positions[3].x, 1); });
  differs("index", [](Scene& s) { std::swap(s.meshes[1].indices[4], s.meshes[1].indices[5]); });
  differs("line", [](Scene& s) { s.meshes[1].lineIndices[1] = 3; });
  differs("point", [](Scene& s) { s.meshes[1].pointIndices[0] = 4; });
  differs("no point", [](Scene& s) { s.meshes[1].pointIndices.clear(); });
  differs("material", [](Scene& s) { s.meshes[0].material = 1; });
  differs("bounds", [](Scene& s) { flipBit(s.meshes[1].bounds.max.z, 2); });
  differs("instance", [](Scene& s) { flipBit(s.instances[0].world[1][1], 0); });
  differs("instance mesh", [](Scene& s) { s.instances[1].mesh = 0; });
  differs("no instance", [](Scene& s) { s.instances.pop_back(); });
  differs("materials", [](Scene& s) { s.materials.emplace_back(); });
  EXPECT_EQ(seen.size(), 17u);  // and each change its own value

  Scene shading = original;  // what the materials and images say is not geometry
  shading.materials[1].baseColorFactor = glm::vec4(0.5f);
  shading.materials[0].baseColorTexture.texture = 0;
  shading.images[0].rgba[3] = 1;
  shading.meshes[0].name = "renamed";
  shading.instances[1].nodeName = "renamed";
  EXPECT_EQ(geometryFingerprint(shading), h);
}

// Above 4 MiB the meshes are hashed on two threads: each mesh's digests are those it has
// hashed alone, in the scene's order, and a change in either half of the meshes counts.
TEST(MeshDigests, ALargeSceneHashedOnTwoThreadsGivesEachMeshItsOwnDigests) {
  Scene large;
  const builder::MeshData data = builder::makeSphere(1.0f, 160, 80);
  for (int k = 0; k < 24; ++k) {
    Mesh mesh;
    mesh.positions = data.positions;
    mesh.normals = data.normals;
    mesh.indices = data.indices;
    mesh.positions[static_cast<std::size_t>(k)].x += 1.0f;  // no two alike
    large.meshes.push_back(mesh);
    MeshInstance instance;
    instance.mesh = k;
    large.instances.push_back(instance);
  }
  std::size_t bytes = 0;
  for (const Mesh& m : large.meshes)
    bytes += m.positions.size() * 24 + m.indices.size() * 4;  // positions and normals
  ASSERT_GT(bytes, std::size_t{4} << 20);

  const std::vector<MeshDigests> digests = meshDigests(large);
  ASSERT_EQ(digests.size(), large.meshes.size());
  for (std::size_t k = 0; k < large.meshes.size(); ++k) {
    Scene alone;
    alone.meshes.push_back(large.meshes[k]);
    const MeshDigests own = meshDigests(alone)[0];
    EXPECT_EQ(digests[k].positions, own.positions) << k;
    EXPECT_EQ(digests[k].normals, own.normals) << k;
    EXPECT_EQ(digests[k].indices, own.indices) << k;
  }
  const std::uint64_t shadow = shadowFingerprint(large), geometry = geometryFingerprint(large);
  for (const std::size_t k : {std::size_t{0}, large.meshes.size() - 1}) {
    Scene changed = large;
    flipBit(changed.meshes[k].positions[100].y, 0);
    EXPECT_NE(shadowFingerprint(changed), shadow) << k;
    EXPECT_NE(geometryFingerprint(changed), geometry) << k;
  }
}

}  // namespace
}  // namespace omnishadow::scene_fingerprint_test
