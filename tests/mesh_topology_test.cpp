#include "renderer/scene/mesh_topology.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "scenes/builder/gltf_builder.h"

namespace omnishadow {
namespace {

using builder::MeshData;

bool closed(const MeshData& m) {
  return isClosedSolid(m.positions, m.indices);
}

MeshData flipped(MeshData m) {
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
    std::swap(m.indices[t + 1], m.indices[t + 2]);
  return m;
}

MeshData merged(const MeshData& a, MeshData b, glm::vec3 offset) {
  MeshData m = a;
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  for (glm::vec3& p : b.positions) m.positions.push_back(p + offset);
  for (std::uint32_t i : b.indices) m.indices.push_back(base + i);
  return m;
}

TEST(MeshTopology, BoxesSpheresAndCylindersAreClosedSolids) {
  // makeBox splits its corners per face (flat normals): welding joins them again.
  EXPECT_TRUE(closed(builder::makeBox(glm::vec3(0.5f, 1.0f, 2.0f))));
  EXPECT_TRUE(closed(builder::makeSphere(1.0f, 24, 12)));
  EXPECT_TRUE(closed(builder::makeCylinder(0.5f, 2.0f, 16)));
}

TEST(MeshTopology, SeveralClosedPiecesInOneMeshAreClosed) {
  EXPECT_TRUE(closed(merged(builder::makeBox(glm::vec3(1.0f)), builder::makeBox(glm::vec3(0.5f)),
                            glm::vec3(5, 0, 0))));
  // Overlapping pieces still only ever show front faces first from outside.
  EXPECT_TRUE(closed(merged(builder::makeBox(glm::vec3(1.0f)), builder::makeSphere(1.0f, 12, 6),
                            glm::vec3(0.5f, 0, 0))));
}

TEST(MeshTopology, OpenSheetsAndHolesAreNotClosed) {
  EXPECT_FALSE(closed(builder::makePlane(2.0f)));
  MeshData holed = builder::makeBox(glm::vec3(1.0f));
  holed.indices.resize(holed.indices.size() - 3);  // one triangle missing
  EXPECT_FALSE(closed(holed));
  EXPECT_FALSE(closed(MeshData{}));
}

TEST(MeshTopology, InsideOutPiecesAreNotClosed) {
  // The room's walls seen from inside, and a box with one piece turned inside out: a light
  // outside them would see back faces first.
  EXPECT_FALSE(closed(flipped(builder::makeBox(glm::vec3(1.0f)))));
  EXPECT_FALSE(closed(merged(builder::makeBox(glm::vec3(1.0f)),
                             flipped(builder::makeBox(glm::vec3(0.5f))), glm::vec3(5, 0, 0))));
}

TEST(MeshTopology, InconsistentWindingAndNonManifoldEdgesAreNotClosed) {
  MeshData box = builder::makeBox(glm::vec3(1.0f));
  MeshData oneFlipped = box;
  std::swap(oneFlipped.indices[1], oneFlipped.indices[2]);
  EXPECT_FALSE(closed(oneFlipped));
  // A triangle repeated: its edges now join three triangles.
  MeshData repeated = box;
  repeated.indices.insert(repeated.indices.end(), box.indices.begin(), box.indices.begin() + 3);
  EXPECT_FALSE(closed(repeated));
  // A flat sheet with both sides as triangles: closed edges, but no volume.
  MeshData plane = builder::makePlane(2.0f);
  EXPECT_FALSE(closed(merged(plane, flipped(plane), glm::vec3(0.0f))));
}

TEST(MeshTopology, DegenerateTrianglesAreIgnored) {
  MeshData box = builder::makeBox(glm::vec3(1.0f));
  box.indices.insert(box.indices.end(), {0, 0, 1});
  EXPECT_TRUE(closed(box));
}

}  // namespace
}  // namespace omnishadow
