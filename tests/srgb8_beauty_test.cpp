// The 8-bit beauty (RenderSettings::srgb8Exposure): where the lighting pass encodes the PNG's
// bytes itself, or a pass after it encodes the float target's (blended and see-through
// surfaces), they are the bytes the CPU makes of the float beauty, exactly; where neither can
// (--aa, AOVs) the frame keeps the float beauty.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "renderer/output/display_transform.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/srgb_transfer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::srgb8_beauty_test {
namespace {

using test_support::lookFrom;
using test_support::sharedRenderer;

Frame render(const Scene& scene, const std::vector<Light>& lights, const ViewCamera& camera,
             const RenderSettings& settings) {
  StageTimes times;
  return sharedRenderer().render(scene, lights, glm::vec3(0.02f), camera, settings, times);
}

int addMaterial(Scene& scene, Material material) {
  scene.materials.push_back(material);
  return static_cast<int>(scene.materials.size()) - 1;
}

Material colored(glm::vec4 color) {
  Material m;
  m.baseColorFactor = color;
  m.metallicFactor = 0.0f;
  m.roughnessFactor = 0.6f;
  return m;
}

// A floor, a box and a sphere: shadows, speculars and dark gradients, where the float values
// cross many byte steps.
Scene litScene() {
  Scene scene;
  test::placeMesh(scene, builder::makePlane(8.0f, 4), glm::mat4(1.0f),
                  addMaterial(scene, colored({0.8f, 0.75f, 0.7f, 1.0f})));
  test::placeMesh(scene, builder::makeBox({0.5f, 0.5f, 0.5f}),
                  glm::translate(glm::mat4(1.0f), {-0.8f, 0.5f, 0.0f}),
                  addMaterial(scene, colored({0.9f, 0.2f, 0.1f, 1.0f})));
  Material metal = colored({0.6f, 0.7f, 0.9f, 1.0f});
  metal.metallicFactor = 1.0f;
  metal.roughnessFactor = 0.25f;
  test::placeMesh(scene, builder::makeSphere(0.6f, 32, 16),
                  glm::translate(glm::mat4(1.0f), {0.9f, 0.6f, 0.3f}), addMaterial(scene, metal));
  return scene;
}

// litScene() and a blended box, which the 8-bit target cannot take.
Scene glassScene() {
  Scene glass = litScene();
  Material blended = colored({0.2f, 0.5f, 0.9f, 0.4f});
  blended.alphaMode = AlphaMode::Blend;
  test::placeMesh(glass, builder::makeBox({0.3f, 0.3f, 0.3f}),
                  glm::translate(glm::mat4(1.0f), {0.0f, 1.5f, 1.0f}), addMaterial(glass, blended));
  return glass;
}

std::vector<Light> litLights() {
  Light point;
  point.name = "point";
  point.position = {0.5f, 2.5f, 1.5f};
  point.intensity = 12.0f;
  point.shadow.resolution = 256;
  point.shadow.filter = ShadowFilter::Pcf;
  Light spot;
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.position = {-2.5f, 3.0f, 2.0f};
  spot.direction = glm::normalize(glm::vec3(2.0f, -3.0f, -2.0f));
  spot.intensity = 30.0f;
  spot.shadow.resolution = 256;
  spot.shadow.filter = ShadowFilter::Pcss;
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  sun.intensity = 1.5f;
  sun.shadow.resolution = 256;
  sun.shadow.filter = ShadowFilter::Poisson;
  return {point, spot, sun};
}

ViewCamera litCamera(const Scene& scene, int width = 160, int height = 96) {
  return lookFrom(scene, {0.0f, 3.0f, 5.0f}, {0.0f, 0.3f, 0.0f}, width, height);
}

// `encoded` has an 8-bit beauty alone, of width x height, each byte what toSrgb8() makes of
// `linear`'s float beauty with `exposure`, and the picture is not black.
void expectCpuEncoding(const Frame& encoded, const Frame& linear, float exposure, int width,
                       int height) {
  ASSERT_TRUE(encoded.srgb8.has_value());
  EXPECT_TRUE(encoded.beauty.pixels.empty());
  EXPECT_EQ(encoded.srgb8->width, width);
  EXPECT_EQ(encoded.srgb8->height, height);
  const std::vector<std::uint8_t> expected = toSrgb8(linear.beauty, exposure);
  ASSERT_EQ(encoded.srgb8->rgb.size(), expected.size());
  std::size_t differ = 0, lit = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    differ += encoded.srgb8->rgb[i] != expected[i];
    lit += expected[i] > 0;
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(lit, expected.size() / 2);
}

// The bytes of an encoded frame equal toSrgb8() of the float frame, whatever the exposure, the
// shading model or the debug view; the float beauty is then left out.
TEST(Srgb8Beauty, EqualsTheCpuEncodingOfTheFloatBeauty) {
  const Scene scene = litScene();
  const std::vector<Light> lights = litLights();
  const ViewCamera camera = litCamera(scene);
  struct Case {
    float exposure;
    Shading shading;
    DebugView debugView;
  };
  for (const Case& c :
       {Case{0.0f, Shading::Pbr, DebugView::None}, Case{1.5f, Shading::Pbr, DebugView::None},
        Case{-2.25f, Shading::Pbr, DebugView::None}, Case{0.7f, Shading::Phong, DebugView::None},
        Case{0.0f, Shading::Pbr, DebugView::Normals}}) {
    SCOPED_TRACE("exposure " + std::to_string(c.exposure));
    RenderSettings settings{.shading = c.shading, .debugView = c.debugView};
    const Frame linear = render(scene, lights, camera, settings);
    settings.srgb8Exposure = c.exposure;
    const Frame encoded = render(scene, lights, camera, settings);
    expectCpuEncoding(encoded, linear, c.exposure, camera.width, camera.height);
  }
}

// The readback packs RGBA rows into RGB two pixels at a time: odd widths end with a single one.
TEST(Srgb8Beauty, OddAndNarrowWidthsEqualTheCpuEncodingToo) {
  const Scene scene = litScene();
  const std::vector<Light> lights = litLights();
  for (const int width : {161, 3, 2, 1}) {
    SCOPED_TRACE("width " + std::to_string(width));
    const ViewCamera camera = litCamera(scene, width, 97);
    RenderSettings settings;
    const Frame linear = render(scene, lights, camera, settings);
    settings.srgb8Exposure = 0.0f;
    const Frame encoded = render(scene, lights, camera, settings);
    ASSERT_TRUE(encoded.srgb8.has_value());
    EXPECT_EQ(encoded.srgb8->rgb, toSrgb8(linear.beauty, 0.0f));
  }
}

// Unlit squares whose colors lie on each byte's first float and on the float just below it:
// the pass's byte changes exactly where the CPU's does.
TEST(Srgb8Beauty, EveryByteStepIsWhereTheCpuPutsIt) {
  const std::array<float, 256>& steps = srgb8Steps();
  Scene scene;
  constexpr int kSide = 16;  // 16 x 16 squares, 255 of them used
  const builder::MeshData square = builder::makePlane(1.0f);
  for (int k = 0; k < kSide * kSide; ++k) {
    const int step = std::min(k, 254);
    Material m;
    m.unlit = true;
    m.baseColorFactor = {steps[step], std::nextafter(steps[step], 0.0f),
                         0.5f * (steps[step] + steps[step + 1 < 255 ? step + 1 : step]), 1.0f};
    test::placeMesh(scene, square,
                    glm::translate(glm::mat4(1.0f), {(k % kSide) - 7.5f, 0.0f, (k / kSide) - 7.5f}),
                    addMaterial(scene, m));
  }
  // Straight down on the squares, 8 pixels each.
  const ViewCamera camera = lookFrom(scene, {0.0f, 20.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 128, 128,
                                     2.0f * glm::degrees(std::atan(8.0f / 20.0f)), {0, 0, -1});
  const Frame frame = render(scene, {}, camera, {.srgb8Exposure = 0.0f});
  ASSERT_TRUE(frame.srgb8.has_value());
  for (int k = 0; k < 255; ++k) {
    const glm::vec4 clip = camera.projection * camera.view *
                           glm::vec4((k % kSide) - 7.5f, 0.0f, (k / kSide) - 7.5f, 1.0f);
    const int x = static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * camera.width);
    const int y = static_cast<int>((0.5f - clip.y / clip.w * 0.5f) * camera.height);
    const std::uint8_t* pixel =
        frame.srgb8->rgb.data() + (static_cast<std::size_t>(y) * camera.width + x) * 3;
    const glm::vec4 color = scene.materials[static_cast<std::size_t>(k)].baseColorFactor;
    SCOPED_TRACE("step " + std::to_string(k + 1));
    EXPECT_EQ(pixel[0], k + 1);
    EXPECT_EQ(pixel[1], k);
    EXPECT_EQ(pixel[0], srgb8(color.r));
    EXPECT_EQ(pixel[1], srgb8(color.g));
    EXPECT_EQ(pixel[2], srgb8(color.b));
  }
}

// Several samples a pixel and AOVs need the float beauty: the frame has it, and no 8-bit one.
TEST(Srgb8Beauty, FramesThePassCannotEncodeKeepTheFloatBeauty) {
  const std::vector<Light> lights = litLights();
  const Scene plain = litScene();
  struct Case {
    const char* what;
    RenderSettings settings;
  };
  for (const Case& c : {Case{"aa", {.antialiasing = 4, .srgb8Exposure = 0.0f}},
                        Case{"aovs", {.aovs = true, .srgb8Exposure = 0.0f}}}) {
    SCOPED_TRACE(c.what);
    const ViewCamera camera = litCamera(plain);
    const Frame frame = render(plain, lights, camera, c.settings);
    EXPECT_FALSE(frame.srgb8.has_value());
    EXPECT_EQ(frame.beauty.pixels.size(),
              static_cast<std::size_t>(camera.width) * camera.height * 4);
  }
}

// Blended and see-through surfaces need the float target; the frame's 8-bit beauty is then
// encoded from it on the GPU (Srgb8Resolve) or on the CPU as its bands are read back: the same
// bytes as toSrgb8() of the float frame, at odd sizes and exposures too, and the masks' object
// ids the same as beside the float beauty. Auto, with either, gives the same.
TEST(Srgb8Beauty, FloatFramesEncodedOnTheGpuOrInBandsEqualTheCpuEncoding) {
  const std::vector<Light> lights = litLights();
  const Scene glass = glassScene();
  Scene window = litScene();
  Material clear = colored({0.9f, 0.9f, 0.95f, 1.0f});
  clear.transmissionFactor = 0.8f;
  test::placeMesh(window, builder::makeBox({0.4f, 0.4f, 0.05f}),
                  glm::translate(glm::mat4(1.0f), {0.0f, 0.8f, 1.5f}), addMaterial(window, clear));
  ASSERT_TRUE(hasTransmission(window.materials.back()));
  struct Case {
    const char* what;
    const Scene* scene;
    int width, height;
    float exposure;
    bool objectIds;
  };
  for (const Case& c : {Case{"blended", &glass, 160, 96, 0.0f, false},
                        Case{"blended, odd size, exposure", &glass, 61, 37, -1.25f, false},
                        Case{"blended, ids", &glass, 160, 96, 0.5f, true},
                        Case{"blended, two threads encode", &glass, 704, 403, 0.25f, false},
                        Case{"see-through", &window, 97, 64, 0.75f, false}}) {
    const ViewCamera camera = litCamera(*c.scene, c.width, c.height);
    const Frame linear = render(*c.scene, lights, camera, {.objectIds = c.objectIds});
    for (const FloatBeautyEncoding encoder :
         {FloatBeautyEncoding::Gpu, FloatBeautyEncoding::CpuInBands, FloatBeautyEncoding::Auto}) {
      SCOPED_TRACE(::testing::Message() << c.what << ", encoder " << static_cast<int>(encoder));
      const Frame encoded = render(
          *c.scene, lights, camera,
          {.objectIds = c.objectIds, .srgb8Exposure = c.exposure, .floatBeautyEncoding = encoder});
      expectCpuEncoding(encoded, linear, c.exposure, c.width, c.height);
      if (c.objectIds) {
        ASSERT_TRUE(linear.objectIds && encoded.objectIds);
        EXPECT_EQ(encoded.objectIds->pixels, linear.objectIds->pixels);
      }
    }
  }
}

// Objects that cover part of the view: the readback takes only the region they may cover
// (FrameTargets::drawn(): here several rectangles, the objects lying apart), and the rest of the
// picture is the background's zeros. Every byte
// still equals toSrgb8() of the float frame, which is read whole: for the 8-bit target and for
// the float one read in bands (one thread and two), at odd sizes, with a sphere cut by the
// view's right edge.
TEST(Srgb8Beauty, FramesCoveringPartOfTheViewEqualTheCpuEncoding) {
  Scene objects;
  test::placeMesh(objects, builder::makeBox({0.5f, 0.5f, 0.5f}),
                  glm::translate(glm::mat4(1.0f), {-0.8f, 0.5f, 0.0f}),
                  addMaterial(objects, colored({0.9f, 0.2f, 0.1f, 1.0f})));
  test::placeMesh(objects, builder::makeSphere(0.6f, 32, 16),
                  glm::translate(glm::mat4(1.0f), {2.6f, 0.6f, 0.3f}),
                  addMaterial(objects, colored({0.6f, 0.7f, 0.9f, 1.0f})));
  Scene glass = objects;
  Material blended = colored({0.2f, 0.5f, 0.9f, 0.4f});
  blended.alphaMode = AlphaMode::Blend;
  test::placeMesh(glass, builder::makeBox({0.3f, 0.3f, 0.3f}),
                  glm::translate(glm::mat4(1.0f), {0.0f, 1.2f, 1.0f}), addMaterial(glass, blended));
  const std::vector<Light> lights = litLights();
  struct Case {
    const char* what;
    const Scene* scene;
    int width, height;
    float exposure;
  };
  for (const Case& c :
       {Case{"opaque", &objects, 160, 96, 0.0f}, Case{"opaque, odd size", &objects, 61, 37, 0.5f},
        Case{"blended", &glass, 160, 96, 0.0f}, Case{"blended, odd size", &glass, 97, 61, -0.75f},
        Case{"blended, two threads encode", &glass, 704, 403, 0.25f}}) {
    SCOPED_TRACE(c.what);
    const ViewCamera camera =
        lookFrom(*c.scene, {0.0f, 1.5f, 3.5f}, {0.2f, 0.5f, 0.0f}, c.width, c.height, 40.0f);
    const Frame linear = render(*c.scene, lights, camera, {});
    const std::vector<std::uint8_t> expected = toSrgb8(linear.beauty, c.exposure);
    // The objects cover part of the view, and reach its right edge.
    std::size_t background = 0, rightEdge = 0;
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        const std::uint8_t* rgb = &expected[(static_cast<std::size_t>(y) * c.width + x) * 3];
        const bool lit = rgb[0] != 0 || rgb[1] != 0 || rgb[2] != 0;
        background += !lit;
        rightEdge += lit && x == c.width - 1;
      }
    ASSERT_GT(background, expected.size() / 3 / 3);
    ASSERT_LT(background, expected.size() / 3 * 9 / 10);
    ASSERT_GT(rightEdge, 0u);
    const Frame encoded = render(*c.scene, lights, camera, {.srgb8Exposure = c.exposure});
    ASSERT_TRUE(encoded.srgb8.has_value());
    EXPECT_EQ(encoded.srgb8->rgb, expected);
  }
}

// FloatBeautyEncoding::Caller keeps the float beauty of such a frame for the caller to encode.
TEST(Srgb8Beauty, FloatFramesLeftToTheCpuKeepTheFloatBeauty) {
  const Scene glass = glassScene();
  const ViewCamera camera = litCamera(glass);
  const Frame frame =
      render(glass, litLights(), camera,
             {.srgb8Exposure = 0.0f, .floatBeautyEncoding = FloatBeautyEncoding::Caller});
  EXPECT_FALSE(frame.srgb8.has_value());
  EXPECT_EQ(frame.beauty.pixels.size(), static_cast<std::size_t>(camera.width) * camera.height * 4);
}

// The pass keeps its 8-bit targets for the next frame of the same size, and a float frame in
// between takes its own: each frame is what it would be alone, at an odd size too.
TEST(Srgb8Beauty, EncodedAndFloatFramesTakeTurnsOnOneRenderer) {
  const Scene scene = litScene();
  const std::vector<Light> lights = litLights();
  const ViewCamera camera = litCamera(scene, 61, 37);
  const Frame first = render(scene, lights, camera, {.srgb8Exposure = 0.5f});
  const Frame linear = render(scene, lights, camera, {});
  const Frame again = render(scene, lights, camera, {.srgb8Exposure = 0.5f});
  ASSERT_TRUE(first.srgb8 && again.srgb8);
  EXPECT_EQ(first.srgb8->rgb, again.srgb8->rgb);
  EXPECT_EQ(first.srgb8->rgb, toSrgb8(linear.beauty, 0.5f));
}

}  // namespace
}  // namespace omnishadow::srgb8_beauty_test
