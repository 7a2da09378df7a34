#pragma once

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "renderer/gl/egl_context.h"
#include "renderer/passes/gpu_scene.h"
#include "renderer/passes/shadow_pass.h"

namespace omnishadow {

// One light's map for the worker to draw (ShadowPass::render's arguments and its result).
struct ShadowJob {
  const Light* light = nullptr;
  const LightShadowPlan* plan = nullptr;
  ShadowGroupTextures* target = nullptr;
  int flatCastersLeftOut = 0;  // filled by the worker
  // ShadowPass::planDraws()'s result, when the renderer worked it out ahead; else null.
  const ShadowPass::LightDraws* planned = nullptr;
};

// Draws some lights' shadow maps in a second GL context, on a thread of its own, while the
// renderer's context draws the others. For llvmpipe: a context transforms, clips, sets up and
// bins every triangle into its 64x64 tiles on the thread that issues the draws, and its
// rasterizer threads (shared by the process's contexts) rasterize each binned pass tile by tile.
// A light whose casters are many small triangles (WhackAMole's mole: 86k triangles in a few
// tiles of one face) costs its issuing thread as much as it costs the rasterizer, so with one
// context the lights take turns at binning; two contexts bin two lights at once
// (docs/performance.md). The maps are the same as one context draws: the same shaders, state
// and commands.
class ShadowWorker {
 public:
  static constexpr const char* kThreadName = "omni-shadows";

  // Starts the thread, which makes its context sharing `renderer`'s objects; returns at once.
  ShadowWorker(const EglContext& renderer, bool debug);
  ~ShadowWorker();  // stops the thread; call after finish()
  ShadowWorker(const ShadowWorker&) = delete;
  ShadowWorker& operator=(const ShadowWorker&) = delete;

  // Starts drawing `jobs` once the commands the calling thread's context has issued so far have
  // completed (its clears and uploads), and returns. Everything passed must stay as it is until
  // finish(). Throws RenderError when the worker's context could not be made (nothing started).
  void start(const GpuScene& scene, const SceneCasters& casters, std::vector<ShadowJob>& jobs,
             ShadowPassStrategy strategy, bool everyCaster);
  // Waits until the jobs' maps are complete; rethrows what drawing them threw.
  void finish();

 private:
  struct Task {
    const GpuScene* scene = nullptr;
    const SceneCasters* casters = nullptr;
    std::vector<ShadowJob>* jobs = nullptr;
    ShadowPassStrategy strategy = ShadowPassStrategy::Auto;
    bool everyCaster = false;
    GLsync ready = nullptr;  // the renderer's commands so far
  };
  void run(const EglContext& renderer, bool debug);
  void draw(ShadowPass& pass, const Task& task);

  std::mutex mutex_;
  std::condition_variable changed_;
  enum class State { Starting, Idle, Working, Done, Failed, Stopping } state_ = State::Starting;
  Task task_;
  std::exception_ptr error_;  // of the context (Failed) or of the last task (Done)
  std::thread thread_;
};

}  // namespace omnishadow
