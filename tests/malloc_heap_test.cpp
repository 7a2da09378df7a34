// malloc's heap as the CLI sets it up for batches and frame sequences (cli/malloc_heap.h): the
// heap's top asks for huge pages exactly where its first fresh pages were dear. (That a batch
// draws the same pictures with and without it: memory_warmup_test.cpp.)
#include "cli/malloc_heap.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/support/memory_mappings.h"

namespace omnishadow::cli::malloc_heap_test {
namespace {

using test_support::hasFlag;
using test_support::kernelHasHugePages;
using test_support::mappingFlags;

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
// A block carved after the advice starts where the advised block started only in a fresh heap:
// a process of its own (a death test), which exits 0 when the check holds.
void exitWhetherTheTopAsksForHugePagesExactlyWhereFaultsWereDear() {
  constexpr std::size_t kAdvised = std::size_t{64} << 20;
  useOneKeptHeap();
  const HeapTopAdvice advice = adviseHeapTop(kAdvised);
  char* carved = static_cast<char*>(std::malloc(kAdvised - (std::size_t{1} << 20)));
  if (!carved) std::_Exit(2);
  // Whole 2 MiB spans past the measured pages, and the last whole span.
  const std::string middle = mappingFlags(carved + kAdvised / 2);
  const std::string last = mappingFlags(carved + kAdvised - (std::size_t{4} << 20));
  std::fprintf(stderr, "%.1f us a page, huge %d\nmiddle: %s\nlast: %s\n",
               advice.pageFaultMicroseconds, advice.hugePages ? 1 : 0, middle.c_str(),
               last.c_str());
  const bool holds =
      advice.pageFaultMicroseconds > 0.0 &&
      advice.hugePages == (advice.pageFaultMicroseconds >= kDearPageFaultMicroseconds) &&
      hasFlag(middle, "hg") == advice.hugePages && hasFlag(last, "hg") == advice.hugePages;
  std::_Exit(holds ? 0 : 1);
}

TEST(MallocHeapDeathTest, TheTopAsksForHugePagesExactlyWhereItsFirstPagesWereDear) {
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(exitWhetherTheTopAsksForHugePagesExactlyWhereFaultsWereDear(),
              ::testing::ExitedWithCode(0), "");
}

// A heap that cannot give the bytes asked for is left alone and measured as nothing.
TEST(MallocHeap, AHeapThatCannotGiveTheBytesIsLeftAlone) {
  const HeapTopAdvice advice = adviseHeapTop(~std::size_t{0} >> 1);
  EXPECT_EQ(advice.pageFaultMicroseconds, 0.0);
  EXPECT_FALSE(advice.hugePages);
}

TEST(MallocHeap, IsSetUpUnlessTurnedOff) {
  ASSERT_EQ(setenv("OMNISHADOW_MEMORY_WARMUP", "0", 1), 0);
  EXPECT_FALSE(mallocSetUpWanted());
  ASSERT_EQ(unsetenv("OMNISHADOW_MEMORY_WARMUP"), 0);
  EXPECT_TRUE(mallocSetUpWanted());
}
#endif

}  // namespace
}  // namespace omnishadow::cli::malloc_heap_test
