// Renderers on different threads share nothing (the Python module's "one Renderer per thread",
// the batch's in-process loaders): two threads that each load a textured glTF scene and render
// frames with their own Renderer, at the same time, draw byte for byte what one renderer draws
// alone. Under scripts/test-threads.sh, ThreadSanitizer checks that they touch no common state
// (the loader's, the texture decoders', the shader sources', the second shadow context's).
#include <gtest/gtest.h>

#include <array>
#include <exception>
#include <filesystem>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include "renderer/gl/software_rasterizer.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/view/camera.h"

namespace concurrent_renderers_test {

using namespace omnishadow;

namespace {

const std::filesystem::path kDuck =
    std::filesystem::path(OMNISHADOW_SOURCE_DIR) / "scenes/thirdparty/Duck/Duck.glb";

Light pointLight(const std::string& name, glm::vec3 position) {
  Light light;
  light.name = name;
  light.type = LightType::Point;
  light.position = position;
  light.intensity = 60000.0f;  // the duck is about 160 units across
  light.shadow.resolution = 128;
  return light;
}

// Frame `frame` (0, 1, 2) of the Duck with two shadowed point lights, moved each frame so that
// no frame reuses a map, as an 8-bit beauty.
Frame renderMovedLights(Renderer& renderer, const Scene& scene, int frame) {
  const ViewCamera camera = resolveCamera(scene, {.width = 64, .height = 48});
  RenderSettings settings;
  settings.srgb8Exposure = 0.0f;
  const float shift = 20.0f * static_cast<float>(frame);
  const std::vector<Light> lights = {pointLight("key", {150.0f + shift, 250.0f, 150.0f}),
                                     pointLight("fill", {-200.0f, 150.0f + shift, 100.0f})};
  StageTimes times;
  return renderer.render(scene, lights, glm::vec3(0.05f), camera, settings, times);
}

// Three frames with moved lights: the second and third draw their two maps in two contexts on
// llvmpipe (RenderSettings::parallelShadowMaps), and none reuses a map. The frames' 8-bit
// beauties, in order.
std::vector<std::vector<std::uint8_t>> renderFrames() {
  const Scene scene = loadGltf(kDuck);
  Renderer renderer(ContextOptions{});
  const bool software = gl::isLlvmpipe(renderer.glDescription());
  std::vector<std::vector<std::uint8_t>> frames;
  for (int frame = 0; frame < 3; ++frame) {
    const Frame drawn = renderMovedLights(renderer, scene, frame);
    EXPECT_EQ(drawn.shadowMapsRendered, 2);
    EXPECT_EQ(drawn.shadowMapsInParallel, software && frame > 0 ? 1 : 0);
    frames.push_back(drawn.srgb8 ? drawn.srgb8->rgb : std::vector<std::uint8_t>{});
  }
  return frames;
}

}  // namespace

TEST(ConcurrentRenderers, TwoThreadsDrawWhatOneRendererDrawsAlone) {
  const std::vector<std::vector<std::uint8_t>> alone = renderFrames();
  ASSERT_EQ(alone.size(), 3u);
  ASSERT_FALSE(alone[0].empty());
  EXPECT_NE(alone[0], alone[2]);  // the lights moved: the frames are not all one picture

  std::array<std::vector<std::vector<std::uint8_t>>, 2> together;
  std::array<std::exception_ptr, 2> errors;
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < together.size(); ++t)
    threads.emplace_back([&, t] {
      try {
        together[t] = renderFrames();
      } catch (...) {
        errors[t] = std::current_exception();
      }
    });
  for (std::thread& thread : threads) thread.join();
  for (std::size_t t = 0; t < together.size(); ++t) {
    SCOPED_TRACE(::testing::Message() << "thread " << t);
    if (errors[t]) std::rethrow_exception(errors[t]);
    EXPECT_EQ(together[t], alone);
  }
}

// EGL initializes a display once per process: a renderer that ends while another on the same
// display lives must leave it initialized, or the other can make no context after that (its
// second shadow context, on the next frame with two maps). Found as this file's first test
// failing under load: one thread's renderer ended before the other made its worker.
TEST(ConcurrentRenderers, ARendererThatEndsLeavesTheOthersDisplayInitialized) {
  const Scene scene = loadGltf(kDuck);
  auto first = std::make_unique<Renderer>(ContextOptions{});
  const bool software = gl::isLlvmpipe(first->glDescription());
  std::promise<void> secondMadeAFrame, firstEnded;
  std::vector<Frame> frames;
  std::exception_ptr error;
  std::thread second([&] {
    bool signalled = false;
    try {
      Renderer renderer(ContextOptions{});
      for (int frame = 0; frame < 3; ++frame) {
        if (frame == 1) {
          signalled = true;
          secondMadeAFrame.set_value();
          firstEnded.get_future().wait();
        }
        frames.push_back(renderMovedLights(renderer, scene, frame));
      }
    } catch (...) {
      error = std::current_exception();
      if (!signalled) secondMadeAFrame.set_value();
    }
  });
  secondMadeAFrame.get_future().wait();
  first.reset();
  firstEnded.set_value();
  second.join();
  if (error) std::rethrow_exception(error);
  ASSERT_EQ(frames.size(), 3u);
  for (std::size_t frame = 1; frame < frames.size(); ++frame) {
    SCOPED_TRACE(::testing::Message() << "frame " << frame);
    EXPECT_EQ(frames[frame].shadowMapsInParallel, software ? 1 : 0);
    EXPECT_TRUE(frames[frame].warnings.empty())
        << (frames[frame].warnings.empty() ? "" : frames[frame].warnings.front());
  }
  // And a renderer made after both is whole too.
  Renderer later(ContextOptions{});
  EXPECT_FALSE(later.glDescription().empty());
}

// Renderers on one thread (a Python session that makes a new Renderer before the old one
// goes): each draws in its own context, whichever was made or ended last. Interleaved frames
// are those of a renderer alone, and the one left after the other ended still draws them.
TEST(ConcurrentRenderers, RenderersOnOneThreadDrawInTheirOwnContexts) {
  const std::vector<std::vector<std::uint8_t>> alone = renderFrames();
  ASSERT_EQ(alone.size(), 3u);
  const Scene scene = loadGltf(kDuck);
  auto first = std::make_unique<Renderer>(ContextOptions{});
  auto second = std::make_unique<Renderer>(ContextOptions{});  // current now
  auto bytes = [&](Renderer& renderer, int frame) {
    const Frame drawn = renderMovedLights(renderer, scene, frame);
    return drawn.srgb8 ? drawn.srgb8->rgb : std::vector<std::uint8_t>{};
  };
  EXPECT_EQ(bytes(*first, 0), alone[0]);
  EXPECT_EQ(bytes(*second, 0), alone[0]);
  EXPECT_EQ(bytes(*first, 1), alone[1]);
  second.reset();  // ends with no context current
  EXPECT_EQ(bytes(*first, 2), alone[2]);
  auto third = std::make_unique<Renderer>(ContextOptions{});
  EXPECT_EQ(bytes(*third, 0), alone[0]);
  first.reset();  // its objects go in its own context: the third's keep theirs
  EXPECT_EQ(bytes(*third, 1), alone[1]);
  EXPECT_EQ(bytes(*third, 2), alone[2]);
}

}  // namespace concurrent_renderers_test
