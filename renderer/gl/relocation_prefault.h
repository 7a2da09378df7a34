#pragma once

// Faulting in, ahead of the dynamic loader, the pages it relocates while a GL driver loads.
//
// Opening the first EGL display loads the driver, and Mesa's llvmpipe brings LLVM with it
// (libLLVM-15: 381,000 relocations into 8.4 MB). The loader writes into every page of those
// segments, and each first write is a copy-on-write page fault on the thread that opens the
// display: about 2,300 of the 3,300 faults of loading Mesa's driver. Where faults are dear (10-12
// us each in a paravirtualized guest, against 2 elsewhere) that is several milliseconds.
// madvise(MADV_POPULATE_WRITE) makes the same private copies without a fault each, and on
// another thread. dl_iterate_phdr lists a library once it is mapped, before the loader relocates
// it (glibc lists it as it maps it, then maps its dependencies), so a thread that watches the
// list can populate each new library's writable segments meanwhile, and then stays ahead of the
// relocation. The pages hold the same bytes either way: populating copies the file's page as
// the loader's first write would, and the kernel's page table lock orders the two.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace omnishadow {

class RelocationPrefault {
 public:
  // Starts watching for libraries loaded from now on, on a thread of its own. Nothing under
  // valgrind; nothing but failed calls where the kernel has no MADV_POPULATE_WRITE (before
  // Linux 5.14).
  RelocationPrefault();
  // Stops watching and waits for the thread.
  ~RelocationPrefault();
  RelocationPrefault(const RelocationPrefault&) = delete;
  RelocationPrefault& operator=(const RelocationPrefault&) = delete;

  // A writable segment's pages up to the end of its file contents, page-aligned.
  struct Range {
    std::uintptr_t begin = 0;
    std::uintptr_t end = 0;
  };
  // The ranges populated (or tried) so far, for tests.
  std::vector<Range> populated() const;
  // Stops watching and waits for the thread; populated() stays.
  void stop();

 private:
  void watch();

  std::vector<std::uintptr_t> known_;  // load addresses of the libraries already handled
  unsigned long long loads_ = 0;       // dl_phdr_info::dlpi_adds at the last scan
  mutable std::mutex mutex_;           // guards populated_
  std::vector<Range> populated_;
  std::atomic<bool> quit_{false};
  std::thread watcher_;
};

}  // namespace omnishadow
