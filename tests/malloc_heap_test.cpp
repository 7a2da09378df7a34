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
using test_support::mappingName;

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

// setUpMallocHeap() in a fresh process: a 64 MiB block comes from the heap, not from a mapping
// of its own as without it, and a second call changes nothing and says what the first did.
void exitWhetherTheHeapIsSetUpOnce() {
  constexpr std::size_t kLarge = std::size_t{64} << 20;
  char* before = static_cast<char*>(std::malloc(kLarge));
  if (!before) std::_Exit(2);
  before[0] = 1;
  const bool mappedBefore = mappingName(before) != "[heap]";
  std::free(before);
  const MallocHeapSetUp first = setUpMallocHeap();
  const MallocHeapSetUp second = setUpMallocHeap();
  char* after = static_cast<char*>(std::malloc(kLarge));
  if (!after) std::_Exit(2);
  after[0] = 1;
  const std::string name = mappingName(after);
  std::fprintf(stderr, "before: %s, after: %s, applied %d/%d, %.1f/%.1f us\n",
               mappedBefore ? "own mapping" : "heap", name.c_str(), first.applied ? 1 : 0,
               second.applied ? 1 : 0, first.heapTop.pageFaultMicroseconds,
               second.heapTop.pageFaultMicroseconds);
  const bool holds = mappedBefore && first.applied && name == "[heap]" && second.applied &&
                     first.heapTop.pageFaultMicroseconds > 0.0 &&
                     second.heapTop.pageFaultMicroseconds == first.heapTop.pageFaultMicroseconds &&
                     second.heapTop.hugePages == first.heapTop.hugePages;
  std::free(after);
  std::_Exit(holds ? 0 : 1);
}

TEST(MallocHeapDeathTest, IsSetUpOncePerProcess) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(exitWhetherTheHeapIsSetUpOnce(), ::testing::ExitedWithCode(0), "");
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
