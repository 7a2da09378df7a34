#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <future>
#include <thread>
#include <vector>

namespace omnishadow {

// How many parts inParts() should cut `count` items of per-item work (a light's culling, its
// clusters) into: one below 16 items, where threads would cost more than they save; else as many
// as the machine has threads, at most 16 and at least 8 items a part.
inline std::size_t partsFor(std::size_t count) {
  if (count < 16) return 1;
  return std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1,
                                 std::min<std::size_t>(count / 8, 16));
}

// work(part, first, end) over [0, count) cut into `parts` consecutive ranges: this thread does
// part 0, a thread of its own each other. For loops whose ranges write disjoint memory, so that
// the result is the same bytes however many parts there are.
template <class Work>
void inParts(std::size_t count, std::size_t parts, const Work& work) {
  if (parts < 2) {
    work(std::size_t{0}, std::size_t{0}, count);
    return;
  }
  std::vector<std::future<void>> helpers;
  for (std::size_t p = 1; p < parts; ++p)
    helpers.push_back(
        std::async(std::launch::async, work, p, count * p / parts, count * (p + 1) / parts));
  work(std::size_t{0}, std::size_t{0}, count / parts);
  for (std::future<void>& helper : helpers) helper.get();
}

// work(first, end) over [0, count) on `threads` threads of its own, in small consecutive ranges
// taken in order, for a caller that uses the items in order while later ones are still made:
// ready(i) returns once item i is made (rethrowing what its range threw). A GPU's driver fed
// lights as their draws are planned starts on the first lights at once, not after the last is
// planned. As with inParts(), ranges must write disjoint memory. The destructor stops the ranges
// not yet begun and waits for the others (they read what the caller owns).
class InOrderAhead {
 public:
  InOrderAhead(std::size_t count, std::size_t threads,
               std::function<void(std::size_t first, std::size_t end)> work)
      : count_(count), work_(std::move(work)) {
    threads = std::max<std::size_t>(threads, 1);
    // 64 ranges: the first items come after a 64th of the work, not a thread's share of it.
    rangeSize_ = std::max<std::size_t>(1, (count + kRanges - 1) / kRanges);
    const std::size_t ranges = (count + rangeSize_ - 1) / rangeSize_;
    done_.resize(ranges);
    for (std::promise<void>& promise : done_) ready_.push_back(promise.get_future());
    threads = std::min(threads, ranges);
    try {
      for (std::size_t t = 0; t < threads; ++t) threads_.emplace_back([this] { makeRanges(); });
    } catch (...) {
      stop();
      throw;
    }
  }
  ~InOrderAhead() { stop(); }
  InOrderAhead(const InOrderAhead&) = delete;
  InOrderAhead& operator=(const InOrderAhead&) = delete;

  void ready(std::size_t item) {
    const std::size_t range = item / rangeSize_;
    while (waited_ <= range) ready_[waited_++].get();
  }

 private:
  static constexpr std::size_t kRanges = 64;

  void makeRanges() {
    for (std::size_t r = next_++; r < done_.size() && !stopping_; r = next_++) {
      try {
        work_(r * rangeSize_, std::min(count_, (r + 1) * rangeSize_));
        done_[r].set_value();
      } catch (...) {
        done_[r].set_exception(std::current_exception());
      }
    }
  }
  void stop() {
    stopping_ = true;
    for (std::thread& thread : threads_) thread.join();
    threads_.clear();
  }

  std::size_t count_;
  std::function<void(std::size_t, std::size_t)> work_;
  std::size_t rangeSize_ = 1;
  std::vector<std::promise<void>> done_;
  std::vector<std::future<void>> ready_;
  std::size_t waited_ = 0;  // ranges whose ready_ was taken
  std::atomic<std::size_t> next_{0};
  std::atomic<bool> stopping_{false};
  std::vector<std::thread> threads_;
};

}  // namespace omnishadow
