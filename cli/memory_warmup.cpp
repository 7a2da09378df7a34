#include "cli/memory_warmup.h"

#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace omnishadow::cli {

namespace {

bool wanted() {
#if defined(__SANITIZE_ADDRESS__)
  return false;  // AddressSanitizer's allocator quarantines the freed block instead of reusing it
#else
  const char* setting = std::getenv("OMNISHADOW_MEMORY_WARMUP");
  if (setting && std::string_view(setting) == "0") return false;
  // Under valgrind the toucher would only compete with the render for its one running thread.
  const char* preload = std::getenv("LD_PRELOAD");
  return !(preload && std::string_view(preload).find("vgpreload") != std::string_view::npos);
#endif
}

// Asks the kernel to back the block's whole 2 MiB spans with transparent huge pages: one fault
// then maps and zeroes 2 MiB instead of 4 KiB, so the toucher covers the frame's needs (Sundial,
// WhackAMole and test_room use more than 100 MB) in the time the context and the load leave
// it, where 4 KiB faults reached about 70 MB; the frame's textures then also take fewer TLB
// misses. Where transparent huge pages are off ("never"), or none is free, the kernel maps
// 4 KiB pages as before.
void adviseHugePages(char* block, std::size_t bytes) {
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  const auto begin = (reinterpret_cast<std::uintptr_t>(block) + kHuge - 1) & ~(kHuge - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(block) + bytes) & ~(kHuge - 1);
  // NOLINTNEXTLINE(performance-no-int-to-ptr): the block's own pages, aligned
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

}  // namespace

MemoryWarmup::MemoryWarmup(std::size_t bytes) {
  if (bytes == 0 || !wanted()) return;
  // Every block from the heap (no mmap of its own, which would come with fresh pages) and
  // nothing given back to the system below 1 GiB: the warm pages stay for the frame.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  block_ = static_cast<char*>(std::malloc(bytes));
  if (!block_) return;
  bytes_ = bytes;
  adviseHugePages(block_, bytes_);
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  toucher_ = std::thread([this, page] {
    sched_param idle{};
    pthread_setschedparam(pthread_self(), SCHED_IDLE, &idle);
    for (std::size_t at = 0; at < bytes_ && !stop_.load(std::memory_order_relaxed); at += page)
      block_[at] = 0;
  });
}

MemoryWarmup::~MemoryWarmup() {
  finish();
}

void MemoryWarmup::finish() {
  stop_ = true;
  if (toucher_.joinable()) toucher_.join();
  std::free(block_);
  block_ = nullptr;
}

}  // namespace omnishadow::cli
