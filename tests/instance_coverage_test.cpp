// coveredPixelCount(): the pixel centers an instance covers drawn alone (annotation masks'
// unoccludedPixels), counted on the CPU.
#include "renderer/view/instance_coverage.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <random>

namespace omnishadow::instance_coverage_test {
namespace {

constexpr int kWidth = 16, kHeight = 12;

// An orthographic camera at z = 10 looking down -Z, one world unit a pixel, centred on the
// origin: pixel column x, row y (top first) spans world x - w/2 .. x + 1 - w/2, h/2 - y - 1 ..
// h/2 - y.
ViewCamera camera() {
  ViewCamera c;
  c.width = kWidth;
  c.height = kHeight;
  c.eye = {0, 0, 10};
  c.view = glm::lookAt(c.eye, glm::vec3(0), glm::vec3(0, 1, 0));
  c.projection = glm::ortho(-kWidth / 2.0f, kWidth / 2.0f, -kHeight / 2.0f, kHeight / 2.0f);
  c.orthographic = true;
  return c;
}

glm::vec3 corner(double column, double row) {
  return {static_cast<float>(column - kWidth / 2.0), static_cast<float>(kHeight / 2.0 - row), 0};
}

// A scene of one mesh holding the quads [x0, x1) x [y0, y1) of pixels, front faces towards
// the camera (or away from it), drawn by one instance.
Scene quads(const std::vector<std::array<int, 4>>& blocks, bool facingAway = false,
            bool doubleSided = false) {
  Scene scene;
  Mesh mesh;
  for (const auto& [x0, y0, x1, y1] : blocks) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.push_back(corner(x0, y1));
    mesh.positions.push_back(corner(x1, y1));
    mesh.positions.push_back(corner(x1, y0));
    mesh.positions.push_back(corner(x0, y0));
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
  }
  if (facingAway)
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
      std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  if (doubleSided) {
    Material material;
    material.doubleSided = true;
    scene.materials.push_back(material);
    mesh.material = 0;
  }
  scene.meshes.push_back(mesh);
  MeshInstance instance;
  instance.mesh = 0;
  scene.instances.push_back(instance);
  return scene;
}

std::size_t count(const Scene& scene) {
  return coveredPixelCount(scene, scene.instances[0], camera());
}

TEST(InstanceCoverage, CountsThePixelCentersAQuadCovers) {
  EXPECT_EQ(count(quads({{2, 3, 10, 8}})), 40u);
  EXPECT_EQ(count(quads({{0, 0, kWidth, kHeight}})), std::size_t{kWidth * kHeight});
}

TEST(InstanceCoverage, CountsPixelsCoveredTwiceOnceWhereverTheyLie) {
  // Two quads apart, overlapping in 2x2 pixels: 40 + 30 - 4.
  EXPECT_EQ(count(quads({{2, 3, 10, 8}, {8, 6, 14, 11}})), 66u);
  // At opposite corners of the frame.
  EXPECT_EQ(count(quads({{0, 0, 1, 1}, {kWidth - 2, kHeight - 1, kWidth, kHeight}})), 3u);
}

TEST(InstanceCoverage, BackFacesCountOnlyWhenDoubleSided) {
  EXPECT_EQ(count(quads({{2, 3, 10, 8}}, true)), 0u);
  EXPECT_EQ(count(quads({{2, 3, 10, 8}}, true, true)), 40u);
}

TEST(InstanceCoverage, WhatLiesOutsideTheFrameCountsNothing) {
  EXPECT_EQ(count(quads({{kWidth + 2, 0, kWidth + 6, 4}})), 0u);
  EXPECT_EQ(count(quads({{-8, -8, 2, 2}})), 4u);  // only its corner inside
}

TEST(InstanceCoverage, VerticesFarOutsideTheFrameCoverItWhole) {
  Scene scene = quads({});
  scene.meshes[0].positions = {{-1e30f, -1e30f, 0}, {1e30f, -1e30f, 0}, {0, 1e30f, 0}};
  scene.meshes[0].indices = {0, 1, 2};
  EXPECT_EQ(count(scene), std::size_t{kWidth * kHeight});
}

// Triangles of every shape, vertices on a quarter-pixel grid so that the screen positions and
// edge values are exact, many centers exactly on an edge: the count is the geometric one.
TEST(InstanceCoverage, SeededTrianglesCoverExactlyTheCentersInsideOrOnTheirEdges) {
  constexpr int kSide = 16;  // 2/16 is exact: world x, y map to pixel x + 8, 8 - y
  ViewCamera square = camera();
  square.width = square.height = kSide;
  square.projection = glm::ortho(-kSide / 2.0f, kSide / 2.0f, -kSide / 2.0f, kSide / 2.0f);
  std::mt19937 random(19);
  std::uniform_int_distribution<int> quarter(-4 * 4, 4 * (kSide + 4));  // beyond the frame too
  for (int t = 0; t < 3000; ++t) {
    std::array<glm::ivec2, 3> v;  // quarter pixels
    for (glm::ivec2& p : v) p = {quarter(random), quarter(random)};
    if (t % 3 == 0) v[2] = v[0] + (v[1] - v[0]) * 2 + glm::ivec2(t % 2, 0);  // slivers
    const long long area = static_cast<long long>(v[1].x - v[0].x) * (v[2].y - v[0].y) -
                           static_cast<long long>(v[2].x - v[0].x) * (v[1].y - v[0].y);
    std::size_t expected = 0;
    for (int y = 0; y < kSide && area != 0; ++y)
      for (int x = 0; x < kSide; ++x) {
        const glm::ivec2 c(4 * x + 2, 4 * y + 2);
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
          const glm::ivec2 a = v[k], b = v[(k + 1) % 3];
          const long long e = static_cast<long long>(b.x - a.x) * (c.y - a.y) -
                              static_cast<long long>(b.y - a.y) * (c.x - a.x);
          inside = inside && (area > 0 ? e >= 0 : e <= 0);
        }
        expected += inside;
      }
    Scene scene = quads({}, false, true);
    for (const glm::ivec2& p : v)
      scene.meshes[0].positions.push_back(
          {p.x / 4.0f - kSide / 2.0f, kSide / 2.0f - p.y / 4.0f, 0.0f});
    scene.meshes[0].indices = {0, 1, 2};
    ASSERT_EQ(coveredPixelCount(scene, scene.instances[0], square), expected)
        << "triangle " << t << ": (" << v[0].x << ", " << v[0].y << ") (" << v[1].x << ", "
        << v[1].y << ") (" << v[2].x << ", " << v[2].y << ") in quarter pixels";
  }
}

}  // namespace
}  // namespace omnishadow::instance_coverage_test
