#pragma once

#include <cstddef>
#include <thread>

namespace omnishadow {

// work(first, end) over [0, count): when `split` and the machine has more than one core, a
// second thread does [0, count / 2) while this one does [count / 2, count); else this thread
// does it all at once. For loops whose halves write disjoint memory and give the same bytes
// whichever thread runs them (mipmap rows, the sRGB conversion of a frame).
template <class Work>
void inTwoHalves(std::size_t count, bool split, const Work& work) {
  if (!split || std::thread::hardware_concurrency() < 2) {
    work(std::size_t{0}, count);
    return;
  }
  std::thread helper(work, std::size_t{0}, count / 2);
  work(count / 2, count);
  helper.join();
}

}  // namespace omnishadow
