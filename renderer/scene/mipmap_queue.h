#pragma once

#include <condition_variable>
#include <deque>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

#include "renderer/scene/scene.h"

namespace omnishadow {

// mipmapChain()s made one after the other on a thread of their own, in the order they were
// asked for: a scene's upload gives each texture its GL storage and first level while the chain
// of the one before is made (the chains were 70% of a five-texture upload, and the GL's share
// had to wait for them). One thread, not one per chain, so that each chain reuses the memory
// of the last instead of faulting in fresh pages.
class MipmapQueue {
 public:
  // With `ownThread` false (or when no thread can be started), add() makes each chain itself,
  // before it returns: for a single chain, which has nothing to overlap with but the storage
  // of its own texture, and would fault in a second thread's memory for it.
  explicit MipmapQueue(bool ownThread = true) : noThread_(!ownThread) {}
  // Waits for the chain being made; the ones not started yet are dropped.
  ~MipmapQueue();
  MipmapQueue(const MipmapQueue&) = delete;
  MipmapQueue& operator=(const MipmapQueue&) = delete;

  // The chain of `image`, once made. `image` must outlive the future's get() or this queue,
  // whichever comes first. An exception of mipmapChain() (std::bad_alloc) comes out of get().
  std::future<std::vector<Image>> add(const Image& image, bool srgb);

 private:
  struct Job {
    const Image* image = nullptr;
    bool srgb = false;
    std::promise<std::vector<Image>> chain;
  };
  static void make(Job& job);
  void run();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> jobs_;
  bool stop_ = false;
  std::thread thread_;     // started by the first add()
  bool noThread_ = false;  // add() makes each chain itself
};

}  // namespace omnishadow
