#include "cli/memory_warmup.h"

#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>

#include "cli/huge_page_trial.h"
#include "cli/malloc_heap.h"

namespace omnishadow::cli {

namespace {

void advise(std::uintptr_t begin, std::uintptr_t end, int advice) {
  // NOLINTNEXTLINE(performance-no-int-to-ptr): the block's own pages, aligned
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, advice);
}

}  // namespace

MemoryWarmup::MemoryWarmup(std::size_t bytes) {
  if (bytes == 0 || !mallocSetUpWanted()) return;
  // The warm pages stay for the frame (cli/malloc_heap.h). One heap for every thread: the
  // upload's mipmap thread, in an arena of its own, freed 16 MiB a texture that the frame then
  // faulted in anew.
  useOneKeptHeap();
  block_ = static_cast<char*>(std::malloc(bytes));
  if (!block_) return;
  bytes_ = bytes;
  // 4 KiB pages wherever the toucher does not ask for huge ones (cli/huge_page_trial.h), also
  // where the system's setting is "always".
  advise(hugeBegin(), hugeEnd(), MADV_NOHUGEPAGE);
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  // Above the block: what the scene's load allocates while the toucher has the block, and what
  // outgrows the block.
  heapAbove_ = adviseHeapTop();
  toucher_ = std::thread([this, page] { touch(page); });
}

std::uintptr_t MemoryWarmup::hugeBegin() const {
  constexpr std::uintptr_t kHuge = HugePageTrial::kHugePage;
  return (reinterpret_cast<std::uintptr_t>(block_) + kHuge - 1) & ~(kHuge - 1);
}

std::uintptr_t MemoryWarmup::hugeEnd() const {
  constexpr std::uintptr_t kHuge = HugePageTrial::kHugePage;
  return std::max(hugeBegin(), (reinterpret_cast<std::uintptr_t>(block_) + bytes_) & ~(kHuge - 1));
}

void MemoryWarmup::touch(std::size_t page) {
  sched_param idle{};
  pthread_setschedparam(pthread_self(), SCHED_IDLE, &idle);
  constexpr std::uintptr_t kHuge = HugePageTrial::kHugePage;
  const auto begin = reinterpret_cast<std::uintptr_t>(block_);
  const std::uintptr_t end = begin + bytes_;
  HugePageTrial trial(hugeBegin(), hugeEnd());
  // Touches the span holding `cursor` up to `until` (and at most its end) with `touchPage`, a
  // page at a time, in a huge page where the trial asks for one and the toucher has touched none
  // of the span yet.
  const auto touchSpan = [&](std::uintptr_t& cursor, std::uintptr_t until, auto touchPage,
                             const std::atomic<bool>& halt) {
    const std::uintptr_t spanBegin = cursor & ~(kHuge - 1);
    const std::uintptr_t spanEnd = std::min(spanBegin + kHuge, until);
    // The last page touched (cursor - page; the block is not page-aligned) lies before the span.
    const bool huge = cursor - spanBegin < page && trial.asks(spanBegin, spanEnd);
    if (huge) advise(spanBegin, spanEnd, MADV_HUGEPAGE);
    const std::uintptr_t from = cursor;
    const double start = threadCpuMilliseconds();
    for (; cursor < spanEnd && !halt.load(std::memory_order_relaxed); cursor += page)
      touchPage(cursor);
    trial.touched(spanBegin, huge, cursor - from, threadCpuMilliseconds() - start);
    if (pageFaultMicroseconds_.load(std::memory_order_relaxed) == 0.0)
      pageFaultMicroseconds_.store(trial.smallPageMicroseconds());
  };
  std::uintptr_t at = begin;
  while (at < end && !stop_.load(std::memory_order_relaxed))
    touchSpan(
        at, end, [&](std::uintptr_t p) { block_[p - begin] = 0; }, stop_);
  handedOver_.store(true);
  handedOver_.notify_one();
  freed_.wait(false);
  // The block is the heap's now, and some of it may be the frame's: each page of the rest that
  // the frame is expected to need is faulted in without changing a byte. A locked add of 0
  // reads and writes the byte back in one step, so that a store another thread makes to it
  // meanwhile is not lost (x86-64 and AArch64 alike; C++ calls it a race with that thread's
  // plain store, which the hardware does not). A span asked for as a huge page keeps the bytes
  // the frame wrote into it: advice changes how pages yet to fault are mapped, and the span gets
  // a huge page only while none of its pages is mapped.
  while (at < neededEnd_ && !quit_.load(std::memory_order_relaxed))
    touchSpan(
        at, neededEnd_,
        [](std::uintptr_t p) {
          // NOLINTNEXTLINE(performance-no-int-to-ptr): a page of the block, now the heap's
          std::atomic_ref<char>(*reinterpret_cast<char*>(p))
              .fetch_add(0, std::memory_order_relaxed);
        },
        quit_);
}

MemoryWarmup::~MemoryWarmup() {
  finish();
  quit_ = true;
  if (toucher_.joinable()) toucher_.join();
}

void MemoryWarmup::finish(std::size_t neededBytes) {
  if (!block_) return;
  stop_ = true;
  if (toucher_.joinable()) handedOver_.wait(false);
  neededEnd_ = reinterpret_cast<std::uintptr_t>(block_) + std::min(neededBytes, bytes_);
  std::free(block_);
  block_ = nullptr;
  freed_.store(true);
  freed_.notify_one();
}

}  // namespace omnishadow::cli
