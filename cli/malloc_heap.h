#pragma once

// malloc's heap set up for a process that renders: the CLI's, and the Python module's when its
// user asks (omnishadow.use_rendering_heap()), never a library's on its own (the settings are
// the process's).
//
// Every block comes from one heap (no mmap of its own, which would come with fresh pages; one
// arena for every thread, since a thread's own arena would fault in fresh pages where the heap
// has warm ones and keep what it frees from the others), and nothing is given back to the system
// below 1 GiB: what a job or a frame frees serves the next one.
//
// And where a fresh 4 KiB page is dear, the heap's top asks for transparent huge pages. On the
// paravirtualized machines omnishadow is measured on, a 4 KiB page takes 10-14 us to fault in
// (about 7 ms per 2 MiB), while a huge page takes 0.12-0.15 ms, or 1.2-5 ms where the host must
// back its memory again: even the slow huge pages are the cheaper (cli/huge_page_trial.h). There
// a 1280x720 render of Sundial spent 56-86 ms giving its 16.8 MB JPEG its pages one by one, and a
// batch of the 24 sample models took 2.1-2.5 s against 1.3-1.5 s with malloc's heap in huge pages
// (docs/performance.md, issue 19). Where 4 KiB pages are quick, huge pages can be the slower (a
// host backing them again, 4-7 ms against 1), and the heap stays as the system has it.

#include <cstddef>

namespace omnishadow::cli {

// A fresh 4 KiB page costing this many microseconds of the faulting thread's CPU, or more, is
// dear: the heap's top then asks for huge pages, and a render prepares little ahead of its frame.
inline constexpr double kDearPageFaultMicroseconds = 5.0;
// How much of the heap's top asks for huge pages where faults are dear: address space only,
// faulted in as the process uses it.
inline constexpr std::size_t kHugeHeapBytes = std::size_t{512} << 20;

// The calling thread's CPU time: what page faults are timed in (a thread that waits for a core
// does not count the wait as the fault's).
double threadCpuMilliseconds();

// Whether the CLI sets malloc up at all: not when OMNISHADOW_MEMORY_WARMUP is "0", under valgrind
// or AddressSanitizer or ThreadSanitizer (whose allocators ignore mallopt()).
bool mallocSetUpWanted();

// One heap for every thread that keeps what is freed (above).
void useOneKeptHeap();

struct HeapTopAdvice {
  double pageFaultMicroseconds = 0.0;  // what its first fresh 4 KiB pages cost, each
  bool hugePages = false;              // whether the rest asks for huge pages for that
};

// Measures the heap's top on the calling thread (its first few pages, which the next blocks
// carved use) and, where a page is dear, advises the next `bytes` of the heap to be huge pages.
// A zero advice where the heap cannot give `bytes`. Call it after useOneKeptHeap(), which keeps
// the advised memory in the heap.
HeapTopAdvice adviseHeapTop(std::size_t bytes = kHugeHeapBytes);

// What setting the heap up did.
struct MallocHeapSetUp {
  bool applied = false;  // false where mallocSetUpWanted() says no
  HeapTopAdvice heapTop;
};

// For a process that renders or reads large files without the memory warm-up (batches, frame
// sequences, verify, diff, info, the Python module on request): one kept heap with its top
// advised, where the set-up is wanted. Once per process: later calls change nothing and return
// what the first one did.
MallocHeapSetUp setUpMallocHeap();

}  // namespace omnishadow::cli
