#pragma once

// Faulting in memory while a render waits for its GL context and scene.
//
// A single render's first frame pays for fresh memory: llvmpipe zeroes every new texture and
// the kernel maps each 4 KiB page on first touch (Box: about 25,000 page faults, Sundial
// 59,000), on the thread that renders. Opening the GL context and loading the scene leave CPU
// time unused meanwhile. A thread at idle priority (SCHED_IDLE: it runs only on an otherwise
// idle core) touches the pages of a large block of malloc's heap in that time; the block then
// goes back to the heap, where the frame's textures and buffers are carved from pages that are
// already there. malloc is set to serve every block from its heap, one heap for all threads,
// and to keep what is freed, so that they are: a process that renders once and exits. Where
// they fault more quickly than the same bytes in 4 KiB pages, the block gets transparent huge
// pages, which the toucher faults in 2 MiB at a time (cli/huge_page_trial.h), before and after
// it hands the block over.
//
// Everything else a render allocates comes from the heap above the block: the scene's decoded
// textures and buffers while the block is still the toucher's, and whatever outgrows the block
// afterwards. Where a fresh 4 KiB page is dear, that part asks for huge pages from the start
// (cli/malloc_heap.h).
//
// Where the scene loads on every core, the toucher gets little of that time (Sundial: 26 of
// 128 MB), and the frame then faults in what it carves beyond (60 MB in its shadow stage). So
// once the block is the heap's, the toucher goes on at idle priority, while the renderer
// compiles shaders and uploads the scene on one core, up to what the frame is expected to carve
// from the block: it faults each page in with an atomic add of 0 to its first byte, which
// changes no byte of memory the frame may hold by then.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <utility>

#include "cli/malloc_heap.h"

namespace omnishadow::cli {

class MemoryWarmup {
 public:
  // Sets malloc up as above, reserves `bytes` of its heap and starts touching them. Nothing at
  // all when OMNISHADOW_MEMORY_WARMUP is "0" or under valgrind or AddressSanitizer; no block
  // and no thread when the heap cannot give the block.
  explicit MemoryWarmup(std::size_t bytes);
  ~MemoryWarmup();
  MemoryWarmup(const MemoryWarmup&) = delete;
  MemoryWarmup& operator=(const MemoryWarmup&) = delete;

  // Gives the block back to the heap, faulted-in pages and the rest; the toucher goes on over
  // the block's first `neededBytes` (what the frame is expected to need) until it has covered
  // them or the warm-up is destroyed.
  void finish(std::size_t neededBytes = 0);

  // What faulting in a fresh 4 KiB page cost the toucher, in microseconds of its CPU time, once
  // it has measured enough of them (HugePageTrial::kCalibrationBytes); 0 before, or without a
  // toucher.
  double pageFaultMicroseconds() const { return pageFaultMicroseconds_.load(); }
  // Whether a toucher runs: false where the warm-up is turned off or had no block.
  bool active() const { return toucher_.joinable(); }
  // What the heap's first fresh pages above the block cost and whether the heap above them asks
  // for huge pages (zero without a block).
  const HeapTopAdvice& heapAbove() const { return heapAbove_; }
  // The block's whole 2 MiB-aligned spans, [first, second): where the toucher asks for huge
  // pages (empty without a block, or once it is handed over).
  std::pair<std::uintptr_t, std::uintptr_t> blockSpans() const {
    return block_ ? std::pair{hugeBegin(), hugeEnd()} : std::pair<std::uintptr_t, std::uintptr_t>{};
  }

 private:
  void touch(std::size_t page);
  // The block's whole 2 MiB-aligned spans.
  std::uintptr_t hugeBegin() const;
  std::uintptr_t hugeEnd() const;

  char* block_ = nullptr;
  std::size_t bytes_ = 0;
  std::atomic<bool> stop_{false};        // the block is to be handed over
  std::atomic<bool> handedOver_{false};  // the toucher has stopped writing to it
  std::atomic<bool> freed_{false};       // it is the heap's; neededEnd_ is set
  std::atomic<bool> quit_{false};        // the toucher is to end
  std::uintptr_t neededEnd_ = 0;         // where the toucher ends once the block is freed
  std::atomic<double> pageFaultMicroseconds_{0.0};
  HeapTopAdvice heapAbove_;
  std::thread toucher_;
};

}  // namespace omnishadow::cli
