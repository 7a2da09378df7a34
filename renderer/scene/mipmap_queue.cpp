#include "renderer/scene/mipmap_queue.h"

#include <exception>
#include <system_error>
#include <utility>

#include "renderer/scene/image_mipmaps.h"

namespace omnishadow {

MipmapQueue::~MipmapQueue() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

std::future<std::vector<Image>> MipmapQueue::add(const Image& image, bool srgb) {
  Job job;
  job.image = &image;
  job.srgb = srgb;
  std::future<std::vector<Image>> chain = job.chain.get_future();
  if (noThread_) {
    make(job);
    return chain;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  if (!thread_.joinable()) {
    try {
      thread_ = std::thread([this] { run(); });
    } catch (const std::system_error&) {
      // No thread to be had: this one makes the chains, each when it is asked for.
      noThread_ = true;
      const std::lock_guard<std::mutex> lock(mutex_);
      for (Job& queued : jobs_) make(queued);
      jobs_.clear();
      return chain;
    }
  }
  wake_.notify_one();
  return chain;
}

void MipmapQueue::make(Job& job) {
  try {
    job.chain.set_value(mipmapChain(*job.image, job.srgb));
  } catch (...) {
    job.chain.set_exception(std::current_exception());
  }
}

void MipmapQueue::run() {
  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
      if (stop_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    make(job);
  }
}

}  // namespace omnishadow
