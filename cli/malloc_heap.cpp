#include "cli/malloc_heap.h"

#include <malloc.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <string_view>

#include "cli/huge_page_trial.h"
#include "renderer/core/under_valgrind.h"

namespace omnishadow::cli {

double threadCpuMilliseconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

bool mallocSetUpWanted() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return false;
#else
  const char* setting = std::getenv("OMNISHADOW_MEMORY_WARMUP");
  if (setting && std::string_view(setting) == "0") return false;
  return !underValgrind();
#endif
}

void useOneKeptHeap() {
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_ARENA_MAX, 1);
}

HeapTopAdvice adviseHeapTop(std::size_t bytes) {
  // Taken and freed at once: it lies at the heap's top and goes back to malloc's top chunk,
  // which M_TRIM_THRESHOLD keeps; later blocks are carved from it in order, the advice staying
  // with the address range.
  char* top = static_cast<char*>(std::malloc(bytes));
  if (!top) return {};
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  // Few enough to cost 0.5 ms where a fault is dear, enough that one slow fault does not decide.
  constexpr std::uintptr_t kMeasuredPages = 32;
  const std::uintptr_t first = (reinterpret_cast<std::uintptr_t>(top) + page - 1) & ~(page - 1);
  HeapTopAdvice advice;
  if (bytes >= (kMeasuredPages + 1) * page) {
    const double start = threadCpuMilliseconds();
    for (std::uintptr_t i = 0; i < kMeasuredPages; ++i)
      // NOLINTNEXTLINE(performance-no-int-to-ptr): a page of the block just taken
      *reinterpret_cast<volatile char*>(first + i * page) = 0;
    advice.pageFaultMicroseconds =
        (threadCpuMilliseconds() - start) * 1000.0 / static_cast<double>(kMeasuredPages);
    advice.hugePages = advice.pageFaultMicroseconds >= kDearPageFaultMicroseconds;
  }
  constexpr std::uintptr_t kHuge = HugePageTrial::kHugePage;
  const std::uintptr_t begin = (first + kMeasuredPages * page + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(top) + bytes) & ~(kHuge - 1);
  if (advice.hugePages && end > begin)
    // NOLINTNEXTLINE(performance-no-int-to-ptr): the block's own whole spans
    madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
  std::free(top);
  return advice;
}

MallocHeapSetUp setUpMallocHeap() {
  // The heap is the process's, and so is whether it was set up.
  static std::once_flag once;
  static MallocHeapSetUp done;
  std::call_once(once, [] {
    if (!mallocSetUpWanted()) return;
    useOneKeptHeap();
    done = {true, adviseHeapTop()};
  });
  return done;
}

}  // namespace omnishadow::cli
