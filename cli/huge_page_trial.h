#pragma once

// Where the memory warm-up (cli/memory_warmup.h) asks for transparent huge pages.
//
// A huge page normally faults in 0.2-0.7 ms of the faulting thread's CPU, about what the same
// 2 MiB take in 4 KiB pages, with 1/512 of the faults; the warm-up then covers more of the
// frame's needs. But on a virtual machine whose host takes back memory the guest has freed
// (virtio-balloon's free page reporting, as on the machines omnishadow is measured on), a huge
// page the host must back again takes 4-7 ms: 128 MB took 120-300 ms in huge pages against
// 47-70 ms in 4 KiB pages a few seconds after the last process exited, or right after a large
// one did. Within one block, the first huge pages can be quick (memory a process just handed
// back) and the rest slow.
//
// So the toucher asks for a huge page span by span, just before it touches the span, and stops
// asking at the first slow one. The block starts in 4 KiB pages, so that what the toucher does
// not reach is never a huge page the frame would fault in unmeasured.
//
// Plain bookkeeping over addresses, testable without the kernel: the caller asks whether to
// advise the span it is about to touch, touches it, and reports the CPU time that took.

#include <cstdint>

namespace omnishadow::cli {

class HugePageTrial {
 public:
  static constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
  // A huge page slower than this (the faulting thread's CPU time) is one the host had to back
  // again.
  static constexpr double kSlowMilliseconds = 2.0;

  // [hugeBegin, hugeEnd): the block's whole 2 MiB-aligned spans.
  HugePageTrial(std::uintptr_t hugeBegin, std::uintptr_t hugeEnd);

  // Whether to ask for a huge page for the span [spanBegin, spanEnd) before touching it.
  bool asks(std::uintptr_t spanBegin, std::uintptr_t spanEnd) const;
  // The span took `cpuMilliseconds` to touch.
  void touched(std::uintptr_t spanBegin, std::uintptr_t spanEnd, double cpuMilliseconds);
  // Whether huge pages were given up: a span asked for took longer than kSlowMilliseconds.
  bool givenUp() const { return givenUp_; }

 private:
  std::uintptr_t hugeBegin_, hugeEnd_;
  bool givenUp_ = false;
};

}  // namespace omnishadow::cli
