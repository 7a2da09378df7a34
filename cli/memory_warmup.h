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
// Everything else a render allocates comes from the heap above the block: the scene's
// decoded textures and buffers while the block is still the toucher's, and whatever outgrows
// the block afterwards. Where a 4 KiB page fault is dear (kDearPageFaultMicroseconds, measured
// on the heap's first pages above the block), that part of the heap asks for transparent huge
// pages from the start: there even a huge page the host must back again is cheaper than the
// same 2 MiB in 4 KiB pages (cli/huge_page_trial.h), and Sundial's 16.8 MB JPEG took 56-86 ms
// to be given its pages one by one (docs/performance.md, issue 19).
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

namespace omnishadow::cli {

class MemoryWarmup {
 public:
  // A fresh 4 KiB page costing this many microseconds or more is dear: the heap above the block
  // then asks for huge pages, and a render prepares little ahead of its frame.
  static constexpr double kDearPageFaultMicroseconds = 5.0;
  // How much of the heap above the block asks for huge pages where faults are dear: address
  // space only, faulted in as the process uses it.
  static constexpr std::size_t kHugeHeapBytes = std::size_t{512} << 20;

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
  // What the heap's first fresh 4 KiB pages above the block cost this thread, in microseconds
  // of its CPU time each (0 without a block), and whether the heap above them asks for huge
  // pages for that reason.
  double heapPageFaultMicroseconds() const { return heapPageFaultMicroseconds_; }
  bool hugeHeap() const { return hugeHeap_; }

 private:
  void touch(std::size_t page);
  // Measures the heap's fresh pages above the block and, where they are dear, advises the next
  // kHugeHeapBytes of it to be huge pages.
  void adviseHeapAbove(std::size_t page);
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
  double heapPageFaultMicroseconds_ = 0.0;
  bool hugeHeap_ = false;
  std::thread toucher_;
};

}  // namespace omnishadow::cli
