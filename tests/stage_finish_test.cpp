// RenderSettings::finishEachStage: without a glFinish after the upload and the shadow maps (the
// default on GPUs, forced here on any GL), the frames are those of a renderer that finishes
// each stage, and only the finished stages record a wait for the GPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "renderer/gl/software_rasterizer.h"
#include "renderer/render/renderer.h"
#include "tests/support/same_frame.h"
#include "tests/support/shadow_stage.h"
#include "tests/support/shared_renderer.h"

namespace stage_finish_test {

using namespace omnishadow;
using test_support::lookFrom;

namespace {

std::vector<Light> lights(float shift) {
  std::vector<Light> out;
  for (const LightType type : {LightType::Point, LightType::Spot, LightType::Directional}) {
    Light light;
    light.name = "light" + std::to_string(out.size());
    light.type = type;
    light.position = glm::vec3(1.0f + shift, 3.0f, 0.5f - static_cast<float>(out.size()));
    light.direction = glm::normalize(-light.position);
    light.intensity = type == LightType::Directional ? 2.0f : 15.0f;
    light.outerConeAngle = 0.9f;
    light.shadow.filter = ShadowFilter::Pcf;
    light.shadow.resolution = 128;
    out.push_back(light);
  }
  return out;
}

bool waited(const StageTimes& times, const std::string& stage) {
  return std::any_of(times.waits().begin(), times.waits().end(),
                     [&](const auto& wait) { return wait.first == stage; });
}

}  // namespace

TEST(StageFinish, FramesWithoutAFinishAfterTheShadowMapsAreTheFramesWithOne) {
  Renderer& renderer = test_support::sharedRenderer();
  const Scene scene = test_support::shadowStage();
  const ViewCamera camera = lookFrom(scene, {0.0f, 5.0f, 6.0f}, {0.0f, 0.5f, 0.0f}, 96, 64);
  for (const bool png : {false, true}) {  // the float beauty, and the 8-bit one read back
    SCOPED_TRACE(png ? "8-bit beauty" : "float beauty");
    RenderSettings finished;
    finished.finishEachStage = true;
    finished.readShadowMaps = true;
    if (png) finished.srgb8Exposure = 0.0f;
    RenderSettings flushed = finished;
    flushed.finishEachStage = false;
    // The frame between moves the lights, so that the last frame draws every map again.
    StageTimes finishedTimes, between, flushedTimes;
    const Frame one =
        renderer.render(scene, lights(0.1f), glm::vec3(0.03f), camera, finished, finishedTimes);
    renderer.render(scene, lights(0.2f), glm::vec3(0.03f), camera, finished, between);
    const Frame two =
        renderer.render(scene, lights(0.1f), glm::vec3(0.03f), camera, flushed, flushedTimes);
    EXPECT_EQ(two.shadowMapsRendered, 3);
    // On llvmpipe a second GL context draws some of the maps (passes/shadow_worker.h): its
    // order with the renderer's context must not rest on the upload's glFinish either.
    EXPECT_EQ(two.shadowMapsInParallel > 0, gl::isLlvmpipe(renderer.glDescription()));
    ASSERT_EQ(one.srgb8.has_value(), png);
    test_support::expectSameFrame(one, two, png ? "8-bit beauty" : "float beauty");
    ASSERT_EQ(one.shadowMaps.size(), two.shadowMaps.size());
    for (std::size_t i = 0; i < one.shadowMaps.size(); ++i)
      EXPECT_EQ(one.shadowMaps[i].distances.faces, two.shadowMaps[i].distances.faces);
    ASSERT_EQ(one.planarShadowMaps.size(), two.planarShadowMaps.size());
    for (std::size_t i = 0; i < one.planarShadowMaps.size(); ++i)
      EXPECT_EQ(one.planarShadowMaps[i].distances, two.planarShadowMaps[i].distances);
    EXPECT_TRUE(waited(finishedTimes, "shadow maps"));
    EXPECT_TRUE(waited(finishedTimes, "upload"));
    EXPECT_FALSE(waited(flushedTimes, "shadow maps"));
    EXPECT_FALSE(waited(flushedTimes, "upload"));
    EXPECT_TRUE(waited(flushedTimes, "lighting"));  // where the maps' GPU work is waited for
  }
}

TEST(StageFinish, SpelledAutoOnOrOff) {
  EXPECT_EQ(parseFinishEachStage("on"), std::optional<bool>(true));
  EXPECT_EQ(parseFinishEachStage("off"), std::optional<bool>(false));
  EXPECT_EQ(parseFinishEachStage("auto"), std::nullopt);
  for (const char* name : {"auto", "on", "off"}) EXPECT_TRUE(isFinishEachStageName(name));
  EXPECT_FALSE(isFinishEachStageName("yes"));
  EXPECT_FALSE(isFinishEachStageName("On"));
  EXPECT_FALSE(isFinishEachStageName(""));
}

}  // namespace stage_finish_test
