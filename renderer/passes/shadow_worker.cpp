#include "renderer/passes/shadow_worker.h"

#include <GL/glcorearb.h>
#include <pthread.h>

#include "renderer/core/errors.h"
#include "renderer/gl/context_defaults.h"
#include "renderer/gl/gl_debug.h"

namespace omnishadow {

ShadowWorker::ShadowWorker(const EglContext& renderer, bool debug)
    : thread_([this, &renderer, debug] { run(renderer, debug); }) {}

ShadowWorker::~ShadowWorker() {
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return state_ != State::Starting && state_ != State::Working; });
    state_ = State::Stopping;
  }
  changed_.notify_all();
  thread_.join();
}

void ShadowWorker::run(const EglContext& renderer, bool debug) {
  // Named for perf and top (scripts/frame_cpu.py counts it apart); at most 15 characters.
  pthread_setname_np(pthread_self(), kThreadName);
  std::exception_ptr failure;
  try {
    // Destroyed in this order on this thread: the pass's GL objects, then the context.
    EglContext context(renderer, debug);
    if (debug) gl::enableDebugOutput();
    gl::applyContextDefaults();
    ShadowPass pass;
    {
      std::lock_guard lock(mutex_);
      state_ = State::Idle;
    }
    changed_.notify_all();
    for (;;) {
      Task task;
      {
        std::unique_lock lock(mutex_);
        changed_.wait(lock,
                      [this] { return state_ == State::Working || state_ == State::Stopping; });
        if (state_ == State::Stopping) return;
        task = task_;
      }
      std::exception_ptr error;
      try {
        draw(pass, task);
      } catch (...) {
        error = std::current_exception();
      }
      {
        // Moved, not copied: the thread that takes the error holds its only reference and frees
        // it, after reading it, instead of this one dropping a copy at the same time.
        std::lock_guard lock(mutex_);
        error_ = std::move(error);
        state_ = State::Done;
      }
      changed_.notify_all();
    }
  } catch (...) {
    failure = std::current_exception();
  }
  // Published after the handler has ended, for the same reason.
  {
    std::lock_guard lock(mutex_);
    error_ = std::move(failure);
    state_ = State::Failed;
  }
  changed_.notify_all();
}

void ShadowWorker::draw(ShadowPass& pass, const Task& task) {
  // What the renderer's context has queued on these maps (prepare()'s clears, a lighting pass
  // reading them) must end first: llvmpipe orders one context's passes, not two contexts'.
  GLsync ready = task.ready;
  constexpr GLuint64 kSecond = 1'000'000'000;
  for (;;) {
    const GLenum waited = glClientWaitSync(ready, 0, kSecond);
    if (waited == GL_ALREADY_SIGNALED || waited == GL_CONDITION_SATISFIED) break;
    if (waited == GL_WAIT_FAILED)
      throw RenderError("the shadow worker's wait for the renderer failed");
  }
  const SceneVertexArrays arrays = task.scene->makeVertexArrays();
  for (ShadowJob& job : *task.jobs)
    job.flatCastersLeftOut = pass.render(*task.scene, arrays, *task.casters, *job.light, *job.plan,
                                         *job.target, task.strategy, task.everyCaster);
  glFinish();  // the maps are complete before the renderer's context reads them
}

void ShadowWorker::start(const GpuScene& scene, const SceneCasters& casters,
                         std::vector<ShadowJob>& jobs, ShadowPassStrategy strategy,
                         bool everyCaster) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return state_ != State::Starting; });
  if (state_ == State::Failed) std::rethrow_exception(error_);
  GLsync ready = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // a fence that is never flushed may never signal in another context
  task_ = {&scene, &casters, &jobs, strategy, everyCaster, ready};
  error_ = nullptr;
  state_ = State::Working;
  lock.unlock();
  changed_.notify_all();
}

void ShadowWorker::finish() {
  std::unique_lock lock(mutex_);
  if (state_ != State::Working && state_ != State::Done) return;
  changed_.wait(lock, [this] { return state_ == State::Done; });
  state_ = State::Idle;
  glDeleteSync(task_.ready);
  task_ = {};
  if (std::exception_ptr error = std::exchange(error_, nullptr)) std::rethrow_exception(error);
}

}  // namespace omnishadow
