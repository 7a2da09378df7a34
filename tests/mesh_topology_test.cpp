#include "renderer/scene/mesh_topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>

#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"

namespace omnishadow::mesh_topology_test {
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

// The largest distance of a mesh's triangle corners, moved by `world`, from a plane.
float farthestFrom(const MeshPlane& plane, const MeshData& m, const glm::mat4& world) {
  float farthest = 0.0f;
  for (const std::uint32_t i : m.indices) {
    const glm::vec3 p(world * glm::vec4(m.positions[i], 1.0f));
    farthest = std::max(farthest, std::abs(glm::dot(plane.normal, p) + plane.offset));
  }
  return farthest;
}

TEST(MeshPlane, AFlatMeshHasThePlaneOfItsTriangles) {
  const MeshData floor = builder::makePlane(4.0f, 8);
  const std::optional<MeshPlane> plane = flatMeshPlane(floor.positions, floor.indices);
  ASSERT_TRUE(plane);
  EXPECT_NEAR(std::abs(plane->normal.y), 1.0f, 1e-6f);
  EXPECT_NEAR(plane->offset, 0.0f, 1e-6f);
  EXPECT_EQ(plane->thickness, 0.0f);
  // Both sides as triangles (a two-sided sheet) are still one plane.
  const MeshData sheet = merged(floor, flipped(floor), glm::vec3(0.0f));
  EXPECT_TRUE(flatMeshPlane(sheet.positions, sheet.indices));
}

TEST(MeshPlane, CurvedBentAndEmptyMeshesHaveNone) {
  const MeshData box = builder::makeBox(glm::vec3(1.0f));
  EXPECT_FALSE(flatMeshPlane(box.positions, box.indices));
  const MeshData sphere = builder::makeSphere(1.0f, 16, 8);
  EXPECT_FALSE(flatMeshPlane(sphere.positions, sphere.indices));
  // A 4 m floor with one corner raised by 1 mm: 2.5e-4 of its extent, over the 1e-5 allowed.
  MeshData bent = builder::makePlane(4.0f, 8);
  bent.positions[0].y += 1e-3f;
  EXPECT_FALSE(flatMeshPlane(bent.positions, bent.indices));
  // Raised by 1e-5 m instead: flat, and the plane's thickness covers the corner.
  MeshData nearly = builder::makePlane(4.0f, 8);
  nearly.positions[0].y += 1e-5f;
  const std::optional<MeshPlane> plane = flatMeshPlane(nearly.positions, nearly.indices);
  ASSERT_TRUE(plane);
  EXPECT_GT(plane->thickness, 0.0f);
  EXPECT_LE(farthestFrom(*plane, nearly, glm::mat4(1.0f)), plane->thickness * 1.0001f);
  // Only triangles count: without any, or with only degenerate ones, there is no plane.
  EXPECT_FALSE(flatMeshPlane(nearly.positions, {}));
  EXPECT_FALSE(flatMeshPlane(nearly.positions, {0, 0, 1, 2, 2, 2}));
}

TEST(MeshPlane, ATransformedPlaneHoldsTheTransformedMesh) {
  MeshData wall = builder::makePlane(3.0f, 4);
  wall.positions[5].y += 2e-5f;  // some thickness to carry through the transform
  const std::optional<MeshPlane> local = flatMeshPlane(wall.positions, wall.indices);
  ASSERT_TRUE(local);
  // Stood up, stretched unevenly, moved far from the origin.
  glm::mat4 world = glm::translate(glm::mat4(1.0f), glm::vec3(40.0f, 2.0f, -7.0f));
  world = glm::rotate(world, 1.2f, glm::normalize(glm::vec3(1.0f, 0.3f, -0.4f)));
  world = glm::scale(world, glm::vec3(2.0f, 5.0f, 0.5f));
  const std::optional<MeshPlane> moved = transformedPlane(*local, world);
  ASSERT_TRUE(moved);
  EXPECT_NEAR(glm::length(moved->normal), 1.0f, 1e-6f);
  EXPECT_LE(farthestFrom(*moved, wall, world), moved->thickness + 1e-4f);
  // The thickness scales with the stretch along the normal: 5x here.
  EXPECT_NEAR(moved->thickness, 5.0f * local->thickness, 1e-3f * local->thickness);
  // A transform that flattens the plane's normal direction away has no plane.
  EXPECT_FALSE(transformedPlane(*local, glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 1.0f))));
}

}  // namespace
}  // namespace omnishadow::mesh_topology_test

namespace omnishadow::mesh_topology_test {
namespace {

TEST(WeldedWithin, PositionsWithinTheToleranceOfAnEarlierOneTakeItsValue) {
  const std::vector<glm::vec3> positions = {{0.0f, 0.0f, 0.0f},           {1.0f, 0.0f, 0.0f},
                                            {0.5e-3f, -0.5e-3f, 1e-3f},   {2e-3f, 0.0f, 0.0f},
                                            {1.0f + 0.9e-3f, 0.0f, 0.0f}, {2.9e-3f, 0.0f, 0.0f}};
  // The third is within 1e-3 of the first in every coordinate; the fourth is not (2e-3 in x);
  // the sixth is within it of the fourth, which is a first of its own.
  const std::vector<glm::vec3> welded = weldedWithin(positions, 1e-3f);
  ASSERT_EQ(welded.size(), positions.size());
  EXPECT_EQ(welded[0], positions[0]);
  EXPECT_EQ(welded[1], positions[1]);
  EXPECT_EQ(welded[2], positions[0]);
  EXPECT_EQ(welded[3], positions[3]);
  EXPECT_EQ(welded[4], positions[1]);
  EXPECT_EQ(welded[5], positions[3]);
  EXPECT_EQ(weldedWithin(positions, 0.0f), positions);
}

TEST(WeldedClosedSolid, ASphereOpenByUlpsAtItsSeamAndPoleIsClosedOnceWelded) {
  for (const float radius : {0.5f, 1.0f, 30.0f}) {
    SCOPED_TRACE(radius);
    const MeshData sphere = test::ulpSeamSphere(radius, 32, 16);
    ASSERT_FALSE(closed(sphere));  // the premise: open by an ulp
    const std::optional<std::vector<glm::vec3>> welded =
        checkSolid(sphere.positions, sphere.indices).welded;
    ASSERT_TRUE(welded);
    EXPECT_TRUE(isClosedSolid(*welded, sphere.indices));
    ASSERT_EQ(welded->size(), sphere.positions.size());
    float moved = 0.0f;
    for (std::size_t i = 0; i < welded->size(); ++i)
      moved = std::max(moved, glm::length((*welded)[i] - sphere.positions[i]));
    EXPECT_GT(moved, 0.0f);
    EXPECT_LE(moved, 2e-6f * radius * std::sqrt(3.0f));  // a millionth of the 2r extent
  }
}

// A box whose faces' copies of one corner differ in the last bit, as a generator computing
// each face's corners by its own expression leaves them: every corner is open, and welded.
TEST(WeldedClosedSolid, ABoxOpenByAnUlpAtOneCornerIsClosedOnceWelded) {
  MeshData box = builder::makeBox(glm::vec3(0.5f));
  ASSERT_TRUE(closed(box));
  const glm::vec3 corner = box.positions[0];
  for (std::size_t i = 1; i < box.positions.size(); ++i)
    if (box.positions[i] == corner) box.positions[i].x = std::nextafter(corner.x, 1.0f);
  ASSERT_FALSE(closed(box));
  const SolidCheck check = checkSolid(box.positions, box.indices);
  EXPECT_FALSE(check.closed);
  ASSERT_TRUE(check.welded);
  EXPECT_TRUE(isClosedSolid(*check.welded, box.indices));
}

// Leaves as separate cards are open by design: with more open corners than a quarter of the
// mesh's positions (and over 1,024), nothing is welded (a weld would cost time in proportion to
// the mesh for nothing), and checkSolid says what isClosedSolid says.
TEST(WeldedClosedSolid, MeshesMostlyOfOpenCornersAreLeftAlone) {
  MeshData cards;
  const MeshData card = builder::makePlane(0.1f);
  for (int i = 0; i < 600; ++i) {
    const auto base = static_cast<std::uint32_t>(cards.positions.size());
    for (const glm::vec3& p : card.positions)
      cards.positions.push_back(p + glm::vec3(0.3f * static_cast<float>(i % 30), 0.0f,
                                              0.3f * static_cast<float>(i / 30)));
    for (const std::uint32_t index : card.indices) cards.indices.push_back(base + index);
  }
  const SolidCheck check = checkSolid(cards.positions, cards.indices);
  EXPECT_FALSE(check.closed);
  EXPECT_FALSE(check.welded);
  // So are 100 boxes in one mesh whose faces' copies of every corner differ in the last bit
  // (2,400 open corners): the bound is on how open a mesh is, not on whether welding would
  // close it.
  MeshData boxes;
  for (int i = 0; i < 100; ++i)
    boxes = merged(boxes, builder::makeBox(glm::vec3(0.05f)),
                   glm::vec3(0.2f * static_cast<float>(i), 0, 0));
  const std::vector<glm::vec3> exact = boxes.positions;
  for (std::size_t i = 1; i < exact.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)  // one ulp more for each earlier copy
      if (exact[j] == exact[i]) boxes.positions[i].x = std::nextafter(boxes.positions[i].x, 1e9f);
  EXPECT_FALSE(checkSolid(boxes.positions, boxes.indices).welded);
  // One of them alone (24 open corners) is welded.
  const MeshData one{std::vector<glm::vec3>(boxes.positions.begin(), boxes.positions.begin() + 24),
                     {},
                     {},
                     std::vector<std::uint32_t>(boxes.indices.begin(), boxes.indices.begin() + 36)};
  EXPECT_TRUE(checkSolid(one.positions, one.indices).welded);
  const MeshData sphere = test::ulpSeamSphere(1.0f, 32, 16);
  const SolidCheck seam = checkSolid(sphere.positions, sphere.indices);
  EXPECT_FALSE(seam.closed);
  EXPECT_TRUE(seam.welded);
  const MeshData solid = builder::makeSphere(1.0f, 24, 12);
  EXPECT_TRUE(checkSolid(solid.positions, solid.indices).closed);
}

TEST(WeldedClosedSolid, ClosedMeshesAndRealOpeningsGetNone) {
  const MeshData box = builder::makeBox(glm::vec3(0.5f));
  EXPECT_FALSE(checkSolid(box.positions, box.indices).welded);  // closed as it is
  MeshData holed = test::ulpSeamSphere(1.0f, 32, 16);
  holed.indices.resize(holed.indices.size() - 3);
  EXPECT_FALSE(checkSolid(holed.positions, holed.indices).welded);
  // The seam's second column a ten-thousandth of the extent away: a crack, not rounding.
  MeshData apart = test::ulpSeamSphere(1.0f, 32, 16);
  for (int iy = 1; iy < 16; ++iy)
    apart.positions[static_cast<std::size_t>(iy * 33 + 32)].x += 2e-4f;
  EXPECT_FALSE(checkSolid(apart.positions, apart.indices).welded);
  EXPECT_FALSE(checkSolid({}, {}).welded);
}

}  // namespace
}  // namespace omnishadow::mesh_topology_test
