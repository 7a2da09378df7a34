// A lighting pass clears only the pixels that the last pass on the same targets may have drawn
// (FrameTargets::toClear): whatever came before on a renderer, a frame is the frame alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "renderer/gl/software_rasterizer.h"
#include "renderer/passes/lighting_pass.h"
#include "renderer/render/renderer.h"
#include "scenes/builder/gltf_builder.h"
#include "tests/support/render_heap.h"
#include "tests/support/same_frame.h"
#include "tests/support/scene_objects.h"
#include "tests/support/shared_renderer.h"

namespace omnishadow::partial_clear_test {
namespace {

using test_support::expectSameFrame;
using test_support::lookFrom;
using test_support::sharedRenderer;

// A ball of radius 0.3 at `at` over nothing; with `glass`, a blended square in front of it
// (a blended surface makes the beauty a float one).
Scene ballAt(glm::vec3 at, bool glass) {
  Scene scene;
  Material ball;
  ball.baseColorFactor = {0.8f, 0.3f, 0.2f, 1.0f};
  ball.metallicFactor = 0.0f;
  ball.roughnessFactor = 0.5f;
  scene.materials.push_back(ball);
  test::placeMesh(scene, builder::makeSphere(0.3f, 24, 12), glm::translate(glm::mat4(1.0f), at), 0);
  if (glass) {
    Material tinted = ball;
    tinted.baseColorFactor = {0.2f, 0.5f, 0.9f, 0.4f};
    tinted.alphaMode = AlphaMode::Blend;
    tinted.doubleSided = true;
    scene.materials.push_back(tinted);
    const glm::mat4 square = glm::translate(glm::mat4(1.0f), at + glm::vec3(0, 0, 0.5f)) *
                             glm::rotate(glm::mat4(1.0f), 1.5707964f, glm::vec3(1, 0, 0));
    test::placeMesh(scene, builder::makePlane(0.5f), square, 1);
  }
  return scene;
}

std::vector<Light> keyLight() {
  Light light;
  light.name = "key";
  light.position = {0.5f, 2.0f, 2.0f};
  light.intensity = 20.0f;
  light.shadow.resolution = 128;
  return {light};
}

// The three ways a beauty pass writes its targets: 8-bit sRGB, float (a blended surface), and
// the AOVs with their layer passes, whose targets are cleared to other values per pass.
struct Case {
  std::string name;
  bool glass;
  RenderSettings settings;
};

std::vector<Case> cases() {
  RenderSettings srgb8;
  srgb8.srgb8Exposure = 0.0f;
  RenderSettings aovs;
  aovs.aovs = true;
  aovs.layers.albedo = aovs.layers.diffuse = aovs.layers.specular = true;
  aovs.layers.objectId = aovs.layers.materialId = true;
  return {{"8-bit beauty", false, srgb8}, {"float beauty", true, srgb8}, {"AOVs", false, aovs}};
}

Frame render(const Scene& scene, const ViewCamera& camera, const RenderSettings& settings) {
  StageTimes times;
  return sharedRenderer().render(scene, keyLight(), glm::vec3(0.05f), camera, settings, times);
}

// The ball on the left, then on the right, then on the left again: the last frame is the first
// one, byte for byte, in every target. It fails when a pass clears only what it draws itself
// (the ball on the right would stay), or nothing of what the last pass drew.
TEST(PartialClear, AFrameAfterAnotherIsTheFrameAlone) {
  int size = 0;
  for (const Case& c : cases()) {
    // A size of its own: the renderer makes new targets for the first frame.
    const Scene left = ballAt({-0.7f, 0.0f, 0.0f}, c.glass);
    const Scene right = ballAt({0.7f, 0.1f, 0.0f}, c.glass);
    const ViewCamera camera = lookFrom(left, {0, 0.3f, 3.0f}, {0, 0, 0}, 120 + 2 * size++, 72);
    const Frame first = render(left, camera, c.settings);
    const Frame moved = render(right, camera, c.settings);
    const Frame again = render(left, camera, c.settings);
    expectSameFrame(first, again, c.name);
    if (first.srgb8) {
      EXPECT_FALSE(first.srgb8->rgb == moved.srgb8->rgb) << c.name;
    } else {
      EXPECT_FALSE(first.beauty.pixels == moved.beauty.pixels) << c.name;
    }
  }
}

// Where no surface is, every AOV channel holds what the README gives a pixel without one:
// visibility 1, objectId and materialId -1, every other channel 0. The layer passes clear their
// second target to the ids in one pass and to zero in the other, so this fails when a pass
// takes the other pass's cleared pixels for its own.
TEST(PartialClear, EveryAovHoldsTheBackgroundsValuesWhereNothingIsDrawn) {
  const Case c = cases()[2];
  const Scene left = ballAt({-0.7f, 0.0f, 0.0f}, false);
  const Scene right = ballAt({0.7f, 0.1f, 0.0f}, false);
  const ViewCamera camera = lookFrom(left, {0, 0.3f, 3.0f}, {0, 0, 0}, 131, 70);
  render(left, camera, c.settings);
  for (const Scene* scene : {&right, &left}) {
    const Frame frame = render(*scene, camera, c.settings);
    ASSERT_TRUE(frame.aovs);
    const FloatImage& aovs = *frame.aovs;
    // A corner, and the middle between the two balls' places: no surface at either.
    for (const glm::ivec2 pixel : {glm::ivec2(0, 0), glm::ivec2(65, 35)}) {
      for (std::size_t ch = 0; ch < aovs.channels.size(); ++ch) {
        const std::string& name = aovs.channels[ch];
        const float expected = name.rfind("visibility.", 0) == 0            ? 1.0f
                               : name == "objectId" || name == "materialId" ? -1.0f
                                                                            : 0.0f;
        EXPECT_EQ(aovs.at(pixel.x, pixel.y, static_cast<int>(ch)), expected)
            << name << " at " << pixel.x << "," << pixel.y;
      }
    }
  }
}

// On llvmpipe new frame targets count as cleared to zeros without a clear (FrameTargets's
// madeZeroed), as new shadow textures do (render_test's NewShadowTexturesOfLlvmpipeHoldThe-
// ClearedDepth): the driver fills every texture it makes with zero bytes. Checked on targets
// made where some full of other values were just deleted, with malloc set as `render` sets it
// (test_support::RenderHeap), so that the heap hands back those very bytes.
TEST(PartialClear, NewBeautyTargetsOfLlvmpipeHoldZeros) {
  if (!gl::isLlvmpipe(sharedRenderer().glDescription()))
    GTEST_SKIP() << "the renderer relies on this on llvmpipe only";
  const test_support::RenderHeap heap;
  const int w = 160, h = 90;
  const std::size_t texels = static_cast<std::size_t>(w) * h;
  for (const PassOutputs outputs : {PassOutputs::Beauty, PassOutputs::Srgb8}) {
    const bool bytes = outputs == PassOutputs::Srgb8;
    {
      FrameTargets full(w, h, outputs);
      EXPECT_EQ(full.toClear(0, true),
                TexelRegion(TexelRect{0, 0, w, h}));  // not known to be zeroed
      const float value[4] = {0.75f, 0.5f, 0.25f, 1.0f};
      const GLuint codes[4] = {191, 128, 64, 255};
      if (bytes)
        glClearTexImage(full.color(0), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, codes);
      else
        glClearTexImage(full.color(0), 0, GL_RGBA, GL_FLOAT, value);
      const float depth = 0.5f;
      glClearTexImage(full.depth(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &depth);
      glFinish();
    }
    FrameTargets fresh(w, h, outputs, contract::kMaxVisibilityOutputs, true);
    EXPECT_TRUE(fresh.toClear(0, true).empty());
    EXPECT_EQ(fresh.toClear(0, false),
              TexelRegion(TexelRect{0, 0, w, h}));  // other values: cleared
    std::vector<std::uint32_t> color(texels * 4, 7u);
    glGetTextureImage(fresh.color(0), 0, bytes ? GL_RGBA_INTEGER : GL_RGBA,
                      bytes ? GL_UNSIGNED_INT : GL_FLOAT,
                      static_cast<GLsizei>(color.size() * sizeof(std::uint32_t)), color.data());
    std::vector<float> depths(texels, -1.0f);
    glGetTextureImage(fresh.depth(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      static_cast<GLsizei>(texels * sizeof(float)), depths.data());
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    EXPECT_EQ(std::count(color.begin(), color.end(), 0u), static_cast<std::ptrdiff_t>(texels * 4))
        << (bytes ? "8-bit beauty" : "float beauty");
    EXPECT_EQ(std::count(depths.begin(), depths.end(), 0.0f), static_cast<std::ptrdiff_t>(texels));
  }
}

}  // namespace
}  // namespace omnishadow::partial_clear_test
