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
// What is slow depends on the machine. On some virtual machines every 4 KiB fault is expensive
// (10.1-11.3 us, against 1.7-2 on the one above: 5.2-5.8 ms for 2 MiB), while a huge page takes
// 0.12-0.15 ms where the host still backs the memory and 1.2-3.7 ms where it must back it
// again: there even the slow huge pages are the cheaper. So the bound is the larger of 2 ms and
// what the same 2 MiB took in 4 KiB pages, as measured on the block's own spans that were not
// asked for: the toucher asks for no huge page before it has touched kCalibrationBytes in 4 KiB
// pages (scripts/fault_cost.py measures both kinds of page).
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
  // A huge page slower than this (the faulting thread's CPU time), and slower than the same
  // bytes in 4 KiB pages, is one the host had to back again.
  static constexpr double kSlowMilliseconds = 2.0;
  // The 4 KiB pages touched before huge pages are asked for, which set the bound.
  static constexpr std::uintptr_t kCalibrationBytes = std::uintptr_t{1} << 20;

  // [hugeBegin, hugeEnd): the block's whole 2 MiB-aligned spans.
  HugePageTrial(std::uintptr_t hugeBegin, std::uintptr_t hugeEnd);

  // Whether to ask for a huge page for the span [spanBegin, spanEnd) before touching it.
  bool asks(std::uintptr_t spanBegin, std::uintptr_t spanEnd) const;
  // The toucher touched `touchedBytes` of the span at `spanBegin` in `cpuMilliseconds`: in a
  // huge page it had asked for (`huge`; its first byte faulted the whole page in), or in 4 KiB
  // pages. The rest of a span asked for, touched after the toucher was cut short in it, lies in
  // the huge page and tells nothing.
  void touched(std::uintptr_t spanBegin, bool huge, std::uintptr_t touchedBytes,
               double cpuMilliseconds);
  // Whether huge pages were given up: a span asked for took longer than slowMilliseconds().
  bool givenUp() const { return givenUp_; }
  // The bound: the larger of kSlowMilliseconds and what the spans touched in 4 KiB pages took
  // per 2 MiB.
  double slowMilliseconds() const;
  // What a 4 KiB page took on average, once kCalibrationBytes of them are measured; else 0.
  double smallPageMicroseconds() const;

 private:
  std::uintptr_t hugeBegin_, hugeEnd_;
  bool givenUp_ = false;
  std::uintptr_t askedSpan_ = 1;   // the last span asked for (1: none begins there)
  std::uintptr_t smallBytes_ = 0;  // touched in 4 KiB pages
  double smallMilliseconds_ = 0.0;
};

}  // namespace omnishadow::cli
