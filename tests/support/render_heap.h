#pragma once
// malloc set as `render` sets it (cli/memory_warmup.h: no mmap, no trimming) for one scope, so
// that a test's new blocks come from memory the heap just took back, with its old bytes, rather
// than from fresh zero pages of the kernel's: what tests of "the driver zeroes what it makes"
// need to see. Under AddressSanitizer mallopt does nothing, but its allocator fills the start of
// every new block with 0xbe, which such a check sees as well.
#include <malloc.h>

namespace omnishadow::test_support {

class RenderHeap {
 public:
  RenderHeap() : set_(mallopt(M_MMAP_MAX, 0) == 1 && mallopt(M_TRIM_THRESHOLD, 1 << 30) == 1) {}
  ~RenderHeap() {
    if (!set_) return;
    mallopt(M_MMAP_MAX, 65536);  // glibc's defaults
    mallopt(M_TRIM_THRESHOLD, 128 * 1024);
  }
  RenderHeap(const RenderHeap&) = delete;
  RenderHeap& operator=(const RenderHeap&) = delete;

 private:
  bool set_;
};

}  // namespace omnishadow::test_support
