#include "renderer/gl/relocation_prefault.h"

#include <link.h>
#include <pthread.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstddef>

#include "renderer/core/under_valgrind.h"

namespace omnishadow {
namespace {

struct Scan {
  std::vector<std::uintptr_t>* known;
  unsigned long long* loads;  // the loader's count of libraries loaded, at the last scan
  std::vector<RelocationPrefault::Range> found;
  std::uintptr_t pageSize;
  bool first = true;
};

// The file-backed part of each writable segment of a library not seen before: what relocation
// writes (its bss, beyond the file, is zero-filled memory it does not touch).
int collect(dl_phdr_info* info, std::size_t size, void* data) {
  auto& scan = *static_cast<Scan*>(data);
  // Each library reports the loader's count of loads; where it has not changed since the last
  // scan, the first library ends the scan (most of the watcher's scans).
  if (scan.first && size >= offsetof(dl_phdr_info, dlpi_adds) + sizeof(info->dlpi_adds)) {
    scan.first = false;
    if (info->dlpi_adds == *scan.loads) return 1;
    *scan.loads = info->dlpi_adds;
  }
  const std::uintptr_t base = info->dlpi_addr;
  if (std::find(scan.known->begin(), scan.known->end(), base) != scan.known->end()) return 0;
  scan.known->push_back(base);
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& segment = info->dlpi_phdr[i];
    if (segment.p_type != PT_LOAD || (segment.p_flags & PF_W) == 0 || segment.p_filesz == 0)
      continue;
    const std::uintptr_t begin = (base + segment.p_vaddr) & ~(scan.pageSize - 1);
    const std::uintptr_t end =
        (base + segment.p_vaddr + segment.p_filesz + scan.pageSize - 1) & ~(scan.pageSize - 1);
    scan.found.push_back({begin, end});
  }
  return 0;
}

}  // namespace

RelocationPrefault::RelocationPrefault() {
  if (underValgrind()) return;
  const auto pageSize = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  // The libraries loaded already are relocated already.
  Scan scan{&known_, &loads_, {}, pageSize};
  dl_iterate_phdr(collect, &scan);
  watcher_ = std::thread([this] { watch(); });
}

RelocationPrefault::~RelocationPrefault() {
  stop();
}

std::vector<RelocationPrefault::Range> RelocationPrefault::populated() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return populated_;
}

void RelocationPrefault::stop() {
  quit_.store(true, std::memory_order_release);
  if (watcher_.joinable()) watcher_.join();
}

void RelocationPrefault::watch() {
  pthread_setname_np(pthread_self(), "omni-prefault");
  const auto pageSize = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  while (!quit_.load(std::memory_order_acquire)) {
    Scan scan{&known_, &loads_, {}, pageSize};
    dl_iterate_phdr(collect, &scan);
    // Outside dl_iterate_phdr, which holds the lock the loader takes to list its next library.
    for (const Range& range : scan.found) {
      // Failures change nothing and are not worth telling apart: a kernel without
      // MADV_POPULATE_WRITE, a segment the loader has relocated and made read-only already
      // (EINVAL here, for small libraries relocated within the watcher's sleep).
      // NOLINTNEXTLINE(performance-no-int-to-ptr): a library's own pages, page-aligned
      madvise(reinterpret_cast<void*>(range.begin), range.end - range.begin, MADV_POPULATE_WRITE);
      const std::lock_guard<std::mutex> lock(mutex_);
      populated_.push_back(range);
    }
    // A library is mapped a few milliseconds before the loader relocates it (its dependencies
    // are mapped in between), and the populating overtakes the loader once it has begun. Each
    // wake-up takes a core from the scene's load for a moment, which every 0.1 ms made
    // Sundial's load (on both cores) 20-30 ms longer.
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

}  // namespace omnishadow
