// The beauty's depth pre-pass is chosen per scene and camera from fragments estimated on the
// CPU (renderer.cpp): frames drawn with and without it are the same picture, byte for byte, and
// a scene whose surfaces hardly hide each other goes without it while one with much overdraw
// keeps it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "renderer/passes/lighting_pass.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::depth_prepass_test {
namespace {

using test_support::lookFrom;
using test_support::sharedRenderer;

Frame render(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
             DepthPrepass prepass = DepthPrepass::Auto) {
  StageTimes times;
  RenderSettings settings;
  settings.srgb8Exposure = 0.0f;
  settings.depthPrepass = prepass;
  return sharedRenderer().render(scene, lights, glm::vec3(0.03f), camera, settings, times);
}

Light keyLight(glm::vec3 position) {
  Light light;
  light.name = "key";
  light.position = position;
  light.intensity = 10.0f;
  light.shadow.resolution = 256;
  return light;
}

std::string scenePath(const std::string& relative) {
  return std::string(OMNISHADOW_SOURCE_DIR) + "/scenes/thirdparty/" + relative;
}

// The pre-pass is llvmpipe's: not drawn on a GPU's driver (NVIDIA's lost pixels with it).
TEST(DepthPrepass, DrawnOnLlvmpipeOnly) {
  EXPECT_TRUE(depthPrepassSupported("llvmpipe (LLVM 15.0.6, 256 bits)"));
  EXPECT_FALSE(depthPrepassSupported("NVIDIA H100 80GB HBM3/PCIe/SSE2"));
  EXPECT_FALSE(depthPrepassSupported("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6)"));
}

// Box alone: the pre-pass would let through exactly the pixels shaded after it, as estimated
// before the first frame, so every frame goes without it. Each frame is the first one's
// picture.
TEST(DepthPrepass, ASceneWithoutOverdrawDropsItAndDrawsTheSamePicture) {
  const Scene scene = loadGltf(scenePath("Box/Box.glb"));
  const std::vector<Light> lights = {keyLight({1.5f, 2.0f, 2.0f})};
  const ViewCamera camera = lookFrom(scene, {1.2f, 1.0f, 1.6f}, {0, 0, 0}, 96, 64);
  const Frame first = render(scene, lights, camera);
  ASSERT_TRUE(first.srgb8);
  EXPECT_FALSE(first.depthPrepass);
  for (int frame = 2; frame <= 12; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const Frame next = render(scene, lights, camera);
    EXPECT_FALSE(next.depthPrepass);
    EXPECT_EQ(next.srgb8->rgb, first.srgb8->rgb);
  }
}

// The Cornell box seen from its open side: the walls behind Suzanne and the boxes are drawn
// where those hide them, so the pre-pass stays.
TEST(DepthPrepass, ASceneWithOverdrawKeepsIt) {
  const Scene scene = loadGltf(scenePath("CornellBoxSuzanne/cornell-box.glb"));
  const glm::vec3 center = scene.bounds.center();
  const float size = 2.0f * scene.bounds.radius();
  const std::vector<Light> lights = {keyLight(center + glm::vec3(0.0f, 0.3f, 0.0f) * size)};
  // Large enough for the hidden fragments to outnumber twice the box's triangles.
  const ViewCamera camera =
      lookFrom(scene, center + glm::vec3(0.0f, 0.0f, 1.2f) * size, center, 192, 128);
  for (int frame = 0; frame < 3; ++frame) {
    const Frame next = render(scene, lights, camera);
    EXPECT_TRUE(next.depthPrepass);
    EXPECT_GT(std::count_if(next.srgb8->rgb.begin(), next.srgb8->rgb.end(),
                            [](std::uint8_t v) { return v > 20; }),
              8000);  // the box fills the picture
  }
}

// A floor and a smaller square above it, in one mesh whose floor triangles come first, a grey
// floor and a blue square listed as two draws, or a floor of many triangles.
enum class FloorAndSquare { OneMesh, TwoDraws, ManyFloorTriangles };

// Such a scene, the square hiding `share` of the floor's pixels from aboveTheSquare().
Scene floorAndSquare(float share, FloorAndSquare layout) {
  Scene scene;
  Material flat;
  flat.unlit = true;
  flat.baseColorFactor = {0.8f, 0.8f, 0.8f, 1.0f};
  scene.materials.push_back(flat);
  flat.baseColorFactor = {0.2f, 0.4f, 0.9f, 1.0f};
  scene.materials.push_back(flat);
  builder::MeshData floor =
      builder::makePlane(2.0f, layout == FloorAndSquare::ManyFloorTriangles ? 40 : 1);
  builder::MeshData square = builder::makePlane(2.0f * std::sqrt(share));
  for (glm::vec3& p : square.positions) p.y += 0.2f;
  if (layout == FloorAndSquare::TwoDraws) {
    test::placeMesh(scene, floor, glm::mat4(1.0f), 0);
    test::placeMesh(scene, square, glm::mat4(1.0f), 1);
  } else {
    // Drawn in one call, the floor's triangles before the square's: no draw order spares them.
    const auto base = static_cast<std::uint32_t>(floor.positions.size());
    floor.positions.insert(floor.positions.end(), square.positions.begin(), square.positions.end());
    floor.normals.insert(floor.normals.end(), square.normals.begin(), square.normals.end());
    floor.uvs.insert(floor.uvs.end(), square.uvs.begin(), square.uvs.end());
    for (const std::uint32_t i : square.indices) floor.indices.push_back(base + i);
    test::placeMesh(scene, floor, glm::mat4(1.0f), 0);
  }
  return scene;
}

ViewCamera aboveTheSquare(const Scene& scene) {
  return lookFrom(scene, {0.0f, 3.0f, 0.01f}, {0, 0, 0}, 96, 96);
}

// The first three frames of floorAndSquare(share, layout) from above the square.
std::vector<Frame> framesWithHiddenShare(float share, FloorAndSquare layout) {
  const Scene scene = floorAndSquare(share, layout);
  const ViewCamera camera = aboveTheSquare(scene);
  std::vector<Frame> frames;
  for (int frame = 0; frame < 3; ++frame) frames.push_back(render(scene, {}, camera));
  return frames;
}

// The pre-pass lets through the floor's fragments that the square hides, a share of the shaded
// ones that the square's area sets. It is dropped below 10% of them (Sundial's 5.5% lost it a
// millisecond a frame) and kept above, from the first frame on; the picture is the same either
// way.
TEST(DepthPrepass, KeptOnlyWhereSurfacesHideATenthOrMore) {
  for (const float share : {0.06f, 0.16f}) {
    SCOPED_TRACE("hidden share " + std::to_string(share));
    const std::vector<Frame> frames = framesWithHiddenShare(share, FloorAndSquare::OneMesh);
    for (const Frame& frame : frames) EXPECT_EQ(frame.depthPrepass, share > 0.1f);
    EXPECT_EQ(frames[2].srgb8->rgb, frames[0].srgb8->rgb);
  }
}

// The same 16%, but the floor has 3,200 triangles: drawing them again costs more than shading
// the 1.2k fragments the pre-pass would spare, so it is dropped.
TEST(DepthPrepass, DroppedWhereItSparesFewFragmentsForItsTriangles) {
  const std::vector<Frame> frames =
      framesWithHiddenShare(0.16f, FloorAndSquare::ManyFloorTriangles);
  for (const Frame& frame : frames) EXPECT_FALSE(frame.depthPrepass);
  EXPECT_EQ(frames[2].srgb8->rgb, frames[0].srgb8->rgb);
}

// A camera that moves is estimated again within eight frames. From above, the square hides 16%
// of the floor: kept. Looking down at a corner of the floor that the square does not reach,
// nothing hides anything: dropped. Every frame is the picture drawn with the pre-pass forced.
TEST(DepthPrepass, AMovedCameraIsEstimatedAgainWithinEightFrames) {
  const Scene scene = floorAndSquare(0.16f, FloorAndSquare::OneMesh);
  const ViewCamera corner = lookFrom(scene, {0.85f, 0.6f, 0.85f}, {0.9f, 0.0f, 0.9f}, 96, 96);
  EXPECT_TRUE(render(scene, {}, aboveTheSquare(scene)).depthPrepass);
  std::vector<Frame> frames;
  for (int frame = 0; frame < 8; ++frame) frames.push_back(render(scene, {}, corner));
  EXPECT_FALSE(frames.back().depthPrepass);
  const Frame forced = render(scene, {}, corner, DepthPrepass::On);
  for (const Frame& frame : frames) EXPECT_EQ(frame.srgb8->rgb, forced.srgb8->rgb);
  // Back above the square, estimated again eight frames later: kept.
  for (int frame = 0; frame < 7; ++frame) render(scene, {}, aboveTheSquare(scene));
  EXPECT_TRUE(render(scene, {}, aboveTheSquare(scene)).depthPrepass);
}

// The square listed after the floor is still drawn before it, being nearer the camera: the
// depth test turns away the floor's hidden fragments, so hardly more pass the pre-pass than are
// shaded, and it is dropped where the scene's order would have kept it (the test above).
TEST(DepthPrepass, NearerSurfacesAreDrawnFirst) {
  const std::vector<Frame> frames = framesWithHiddenShare(0.16f, FloorAndSquare::TwoDraws);
  for (const Frame& frame : frames) EXPECT_FALSE(frame.depthPrepass);
  EXPECT_EQ(frames[2].srgb8->rgb, frames[0].srgb8->rgb);
  // The square is drawn: its blue in the middle of the picture.
  const std::uint8_t* middle = frames[2].srgb8->rgb.data() + (48 * 96 + 48) * 3;
  EXPECT_GT(middle[2], middle[0]);
}

// Two overlapping coplanar squares, the later drawn wins where they tie, with the pre-pass and
// without it; a box in front hides part of both.
TEST(DepthPrepass, TiesGoToTheLastDrawnSurfaceEitherWay) {
  Scene scene;
  const auto flat = [&](glm::vec4 color) {
    Material m;
    m.unlit = true;
    m.baseColorFactor = color;
    scene.materials.push_back(m);
    return static_cast<int>(scene.materials.size()) - 1;
  };
  const builder::MeshData square = builder::makePlane(2.0f);
  test::placeMesh(scene, square, glm::translate(glm::mat4(1.0f), {-0.5f, 0.0f, 0.0f}),
                  flat({1, 0, 0, 1}));
  test::placeMesh(scene, square, glm::translate(glm::mat4(1.0f), {0.5f, 0.0f, 0.0f}),
                  flat({0, 0, 1, 1}));
  test::placeMesh(scene, builder::makeBox({0.3f, 0.3f, 0.3f}),
                  glm::translate(glm::mat4(1.0f), {0.0f, 0.6f, 0.0f}), flat({0, 1, 0, 1}));
  const ViewCamera camera = lookFrom(scene, {0.0f, 5.0f, 0.01f}, {0, 0, 0}, 64, 64);
  const Frame first = render(scene, {}, camera, DepthPrepass::On);
  const Frame second = render(scene, {}, camera);
  ASSERT_TRUE(first.depthPrepass);
  ASSERT_FALSE(second.depthPrepass);  // the squares tie: no more fragments than shaded
  EXPECT_EQ(second.srgb8->rgb, first.srgb8->rgb);
  // In the overlap (x = 0), away from the box (z about 0.9): blue, drawn after red.
  const std::uint8_t* overlap = first.srgb8->rgb.data() + (22 * 64 + 32) * 3;
  EXPECT_EQ(overlap[0], 0);
  EXPECT_EQ(overlap[2], 255);
}

// --depth-prepass on and off: every frame as asked, also those that auto would draw otherwise
// (Box goes without it, the Cornell box keeps it), and the picture auto draws.
// Frames asked for on or off in between leave auto's choice for the scene as it was.
TEST(DepthPrepass, OnAndOffAreDrawnAsAskedWithTheSamePicture) {
  const Scene box = loadGltf(scenePath("Box/Box.glb"));
  const Scene cornell = loadGltf(scenePath("CornellBoxSuzanne/cornell-box.glb"));
  for (const Scene* scene : {&box, &cornell}) {
    SCOPED_TRACE(scene == &box ? "Box" : "Cornell box");
    const glm::vec3 center = scene->bounds.center();
    const float size = 2.0f * scene->bounds.radius();
    const std::vector<Light> lights = {keyLight(center + glm::vec3(0.3f, 0.4f, 0.2f) * size)};
    // Large enough for the Cornell box's hidden fragments to outnumber twice its triangles.
    const ViewCamera camera =
        lookFrom(*scene, center + glm::vec3(0.2f, 0.3f, 1.2f) * size, center, 192, 128);
    const Frame reference = render(*scene, lights, camera);
    ASSERT_TRUE(reference.srgb8);
    EXPECT_EQ(reference.depthPrepass, scene == &cornell);
    for (int frame = 0; frame < 4; ++frame) {
      SCOPED_TRACE("frame " + std::to_string(frame));
      const Frame on = render(*scene, lights, camera, DepthPrepass::On);
      const Frame off = render(*scene, lights, camera, DepthPrepass::Off);
      EXPECT_TRUE(on.depthPrepass);
      EXPECT_FALSE(off.depthPrepass);
      EXPECT_EQ(on.srgb8->rgb, reference.srgb8->rgb);
      EXPECT_EQ(off.srgb8->rgb, reference.srgb8->rgb);
    }
    const Frame again = render(*scene, lights, camera);
    EXPECT_EQ(again.depthPrepass, scene == &cornell);
    EXPECT_EQ(again.srgb8->rgb, reference.srgb8->rgb);
  }
}

TEST(DepthPrepass, SpelledAutoOnOrOff) {
  for (const DepthPrepass p : {DepthPrepass::Auto, DepthPrepass::On, DepthPrepass::Off}) {
    EXPECT_TRUE(isDepthPrepassName(toString(p)));
    EXPECT_EQ(parseDepthPrepass(toString(p)), p);
  }
  EXPECT_FALSE(isDepthPrepassName("yes"));
  EXPECT_FALSE(isDepthPrepassName("On"));
  EXPECT_FALSE(isDepthPrepassName(""));
}

}  // namespace
}  // namespace omnishadow::depth_prepass_test
