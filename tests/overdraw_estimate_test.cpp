// estimateOverdraw(): the fragments a depth pre-pass would let through and the pixels covered,
// from the CPU before anything is drawn, checked against areas worked out by hand.
#include "renderer/view/overdraw_estimate.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "renderer/view/camera.h"

namespace omnishadow::overdraw_estimate_test {
namespace {

constexpr int kWidth = 200, kHeight = 100;
constexpr int kSamples = kWidth * kHeight;  // one a pixel: areas come out exact to a pixel

// A square of side 2 in the z = 0 plane, facing +z (counter-clockwise seen from there).
Mesh square() {
  Mesh mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

// Orthographic, looking down -z from z = 10: one world unit is 10 pixels.
glm::mat4 orthographicView() {
  const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 10), glm::vec3(0), glm::vec3(0, 1, 0));
  return reversedOrthographic(10.0f, 5.0f, 0.1f, 100.0f) * view;
}

glm::mat4 placed(glm::vec3 at, float scale = 1.0f) {
  return glm::scale(glm::translate(glm::mat4(1.0f), at), glm::vec3(scale));
}

// A 20x20-pixel square: 400 pixels covered, each by one fragment, from two triangles.
TEST(OverdrawEstimate, ASquareCoversItsArea) {
  const Mesh mesh = square();
  const OverdrawCounts counts =
      estimateOverdraw({{&mesh, placed({0, 0, 0})}}, orthographicView(), kWidth, kHeight, kSamples);
  EXPECT_EQ(counts.covered, 400u);
  EXPECT_EQ(counts.passed, 400u);
  EXPECT_EQ(counts.triangles, 2u);
}

// A nearer square drawn after a farther one passes where it overlaps it (the pre-pass lets
// those fragments through twice); drawn first, it turns the farther one's away there.
TEST(OverdrawEstimate, OnlyWhatIsDrawnBehindFirstPassesTwice) {
  const Mesh mesh = square();
  const OverdrawSurface far{&mesh, placed({0, 0, 0})};
  const OverdrawSurface near{&mesh, placed({1, 0, 1})};  // overlaps half of the far one
  const OverdrawCounts farFirst =
      estimateOverdraw({far, near}, orthographicView(), kWidth, kHeight, kSamples);
  const OverdrawCounts nearFirst =
      estimateOverdraw({near, far}, orthographicView(), kWidth, kHeight, kSamples);
  EXPECT_EQ(farFirst.covered, 600u);
  EXPECT_EQ(farFirst.passed, 800u);
  EXPECT_EQ(nearFirst.covered, 600u);
  EXPECT_EQ(nearFirst.passed, 600u);
}

// Two squares in one plane: the later one does not pass where they tie (GL_GREATER).
TEST(OverdrawEstimate, TiesDoNotPassTwice) {
  const Mesh mesh = square();
  const OverdrawCounts counts =
      estimateOverdraw({{&mesh, placed({0, 0, 0})}, {&mesh, placed({1, 0, 0})}}, orthographicView(),
                       kWidth, kHeight, kSamples);
  EXPECT_EQ(counts.covered, 600u);
  EXPECT_EQ(counts.passed, 600u);
}

// Seen from behind, a single-sided square is culled and a double-sided one is not; a mirroring
// transform turns which side is the front.
TEST(OverdrawEstimate, BackFacesAreCulledUnlessDoubleSided) {
  const Mesh mesh = square();
  const glm::mat4 turned = glm::rotate(glm::mat4(1.0f), glm::radians(180.0f), glm::vec3(0, 1, 0));
  const glm::mat4 mirrored = glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1));
  const auto covered = [&](const OverdrawSurface& surface) {
    return estimateOverdraw({surface}, orthographicView(), kWidth, kHeight, kSamples).covered;
  };
  EXPECT_EQ(covered({&mesh, turned, true, false}), 0u);
  EXPECT_EQ(covered({&mesh, turned, false, false}), 400u);
  // x mirrored: the triangles turn clockwise on screen, and their front with them.
  EXPECT_EQ(covered({&mesh, mirrored, true, false}), 0u);
  EXPECT_EQ(covered({&mesh, mirrored, true, true}), 400u);
}

// A floor reaching behind the camera, which looks along it: each of its two triangles crosses
// the near plane, and clipped there they still cover everything below the horizon, the lower
// half of the frame.
TEST(OverdrawEstimate, TrianglesCrossingTheNearPlaneAreClipped) {
  Mesh floor;
  floor.positions = {{-1000, 0, 1000}, {1000, 0, 1000}, {1000, 0, -1000}, {-1000, 0, -1000}};
  floor.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from above
  const glm::mat4 view = glm::lookAt(glm::vec3(0, 1, 0), glm::vec3(0, 1, -1), glm::vec3(0, 1, 0));
  const glm::mat4 projection = reversedPerspective(glm::radians(60.0f), 2.0f, 0.1f, 0.0f);
  const OverdrawCounts counts =
      estimateOverdraw({{&floor, glm::mat4(1.0f)}}, projection * view, kWidth, kHeight, kSamples);
  // The far edge, 1000 away, lies a fraction of a pixel below the horizon.
  EXPECT_GE(counts.covered, 200u * 49u);
  EXPECT_LE(counts.covered, 200u * 50u);
  EXPECT_EQ(counts.passed, counts.covered);
}

// A triangle reaching billions of pixels beyond the frame covers all of it: its extent is
// clamped to the frame before it becomes a sample index.
TEST(OverdrawEstimate, ATriangleFarBeyondTheFrameCoversIt) {
  Mesh mesh;
  mesh.positions = {{-1e9f, -1e9f, 0}, {1e9f, -1e9f, 0}, {0, 1e9f, 0}};
  mesh.indices = {0, 1, 2};
  const OverdrawCounts counts =
      estimateOverdraw({{&mesh, glm::mat4(1.0f)}}, orthographicView(), kWidth, kHeight, kSamples);
  EXPECT_EQ(counts.covered, static_cast<std::uint64_t>(kWidth * kHeight));
}

// Fewer samples than pixels: one at the centre of each 4x4-pixel cell, counted as 16 pixels.
// The squares span x 92-112 and 104-124 and y 40-60, so 5 x 5 samples each, 2 x 5 shared.
TEST(OverdrawEstimate, SampledCountsAreScaledToPixels) {
  const Mesh mesh = square();
  const OverdrawSurface far{&mesh, placed({0.2f, 0, 0})};
  const OverdrawSurface near{&mesh, placed({1.4f, 0, 1})};
  const OverdrawCounts counts =
      estimateOverdraw({far, near}, orthographicView(), kWidth, kHeight, kSamples / 16);
  EXPECT_EQ(counts.covered, 40u * 16u);
  EXPECT_EQ(counts.passed, 50u * 16u);
}

}  // namespace
}  // namespace omnishadow::overdraw_estimate_test
