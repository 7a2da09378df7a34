#pragma once

#include <algorithm>
#include <cstddef>
#include <future>
#include <thread>
#include <vector>

namespace omnishadow {

// work(part, first, end) over [0, count) cut into `parts` consecutive ranges: this thread does
// part 0, a thread of its own each other. For loops whose ranges write disjoint memory, so that
// the result is the same bytes however many parts there are.
// How many parts inParts() should cut `count` items of per-item work (a light's culling, its
// clusters) into: one below 16 items, where threads would cost more than they save; else as many
// as the machine has threads, at most 16 and at least 8 items a part.
inline std::size_t partsFor(std::size_t count) {
  if (count < 16) return 1;
  return std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1,
                                 std::min<std::size_t>(count / 8, 16));
}

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

}  // namespace omnishadow
