// The render's memory warm-up (cli/memory_warmup.h): what it does to malloc, that it can be
// turned off, and that it changes no output. A test program of its own: malloc's settings are
// the process's.
#include "cli/memory_warmup.h"

#include <gtest/gtest.h>
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/cli_fixture.h"
#include "tests/support/memory_mappings.h"

namespace omnishadow::cli::memory_warmup_test {
namespace {

using test_support::hasFlag;
using test_support::kernelHasHugePages;
using test_support::mappingFlags;
using test_support::sameBytes;
using test_support::someMappingAsksForHugePages;

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
// Blocks the size of a 1024^2 cube map come from malloc's heap after a warm-up, not from
// mappings of their own (which would start with fresh pages); not before one, or when it is
// turned off. One process, so the order is the test's: off first, then on.
TEST(MemoryWarmup, LargeBlocksComeFromTheHeapOnlyAfterAWarmup) {
  const auto mappedBlocksFor = [](std::size_t bytes) {
    void* block = std::malloc(bytes);
    const int mapped = mallinfo2().hblks;
    std::free(block);
    return mapped;
  };
  constexpr std::size_t kCubeMap = std::size_t{24} << 20;
  ASSERT_EQ(setenv("OMNISHADOW_MEMORY_WARMUP", "0", 1), 0);
  {
    MemoryWarmup off(std::size_t{64} << 20);
    off.finish();
  }
  EXPECT_EQ(mappedBlocksFor(kCubeMap), 1);
  ASSERT_EQ(unsetenv("OMNISHADOW_MEMORY_WARMUP"), 0);
  {
    MemoryWarmup warmup(std::size_t{64} << 20);
    warmup.finish();
    warmup.finish();  // twice is harmless
  }
  EXPECT_EQ(mappedBlocksFor(kCubeMap), 0);
  EXPECT_EQ(mappedBlocksFor(std::size_t{200} << 20), 0);
}

// The toucher reports what a fresh 4 KiB page cost it once it has faulted in a megabyte of
// them: a time a page fault can take, which stays after the hand-over (a render prepares nothing
// ahead of its frame where that is dear).
TEST(MemoryWarmup, ReportsWhatA4KiBPageFaultCostsOnceMeasured) {
  MemoryWarmup warmup(std::size_t{16} << 20);
  // The toucher runs only on an idle core: wait for it.
  for (int i = 0; i < 2000 && warmup.pageFaultMicroseconds() == 0.0; ++i) usleep(10000);
  const double microseconds = warmup.pageFaultMicroseconds();
  EXPECT_GT(microseconds, 0.0);
  EXPECT_LT(microseconds, 10000.0);
  warmup.finish();
  EXPECT_EQ(warmup.pageFaultMicroseconds(), microseconds);
}

// The warm-up measures the heap's first fresh pages above its block on the calling thread, and
// is off entirely where it is turned off.
TEST(MemoryWarmup, MeasuresTheHeapAboveTheBlockAtOnce) {
  ASSERT_EQ(setenv("OMNISHADOW_MEMORY_WARMUP", "0", 1), 0);
  {
    MemoryWarmup off(std::size_t{16} << 20);
    EXPECT_EQ(off.heapAbove().pageFaultMicroseconds, 0.0);
    EXPECT_FALSE(off.heapAbove().hugePages);
  }
  ASSERT_EQ(unsetenv("OMNISHADOW_MEMORY_WARMUP"), 0);
  MemoryWarmup warmup(std::size_t{16} << 20);
  const double microseconds = warmup.heapAbove().pageFaultMicroseconds;
  EXPECT_GT(microseconds, 0.0);
  EXPECT_LT(microseconds, 10000.0);
  EXPECT_EQ(warmup.heapAbove().hugePages, microseconds >= kDearPageFaultMicroseconds);
  warmup.finish();
}

// After a warm-up a thread started later allocates from the main heap, whose pages the warm-up
// touched and where what the others free goes (an arena of its own would fault in fresh pages
// and keep what it frees): its block lies below the program break, where no mapping is.
TEST(MemoryWarmup, ThreadsStartedAfterAWarmupAllocateFromTheWarmedHeap) {
  {
    MemoryWarmup warmup(std::size_t{16} << 20);
    warmup.finish();
  }
  std::uintptr_t block = 0;
  std::thread([&block] {
    void* taken = std::malloc(std::size_t{4} << 20);
    block = reinterpret_cast<std::uintptr_t>(taken);
    std::free(taken);
  }).join();
  ASSERT_NE(block, 0u);
  EXPECT_LT(block, reinterpret_cast<std::uintptr_t>(sbrk(0)));
}

// What the toucher does not reach is in 4 KiB pages ("nh": MADV_NOHUGEPAGE), so that the
// frame never faults in a huge page that nobody timed (cli/huge_page_trial.h). Stopped at once,
// the toucher has reached at most a few of the block's 32 spans.
TEST(MemoryWarmup, WhatTheToucherDoesNotReachIsIn4KiBPages) {
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  constexpr std::size_t kBlock = std::size_t{64} << 20;
  {
    MemoryWarmup warmup(kBlock);
    warmup.finish();
  }
  char* carved = static_cast<char*>(std::malloc(kBlock - (std::size_t{1} << 20)));
  ASSERT_NE(carved, nullptr);
  const std::string tail = mappingFlags(carved + kBlock - (std::size_t{8} << 20));
  std::free(carved);
  ASSERT_FALSE(tail.empty());
  EXPECT_TRUE(hasFlag(tail, "nh")) << tail;
  EXPECT_FALSE(hasFlag(tail, "hg")) << tail;
}

// The toucher asks for huge pages once it has touched a megabyte in 4 KiB pages (which sets
// what a slow huge page is, cli/huge_page_trial.h): from the block's first or second whole span
// on. Where it stops asking (a slow one, or the end of its time) it does not ask again: a cube
// map carved from the first spans lies in huge-page memory, and every span after the first
// one not asked for is in 4 KiB pages.
TEST(MemoryWarmup, HugePagesAreAskedForFromTheStartOfTheBlock) {
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  constexpr std::size_t kBlock = std::size_t{32} << 20;
  constexpr std::size_t kSpan = std::size_t{2} << 20;
  {
    MemoryWarmup warmup(kBlock);
    // The toucher runs only on an idle core: wait until it has asked for its first span.
    const auto [begin, end] = warmup.blockSpans();
    ASSERT_LT(begin, end);
    for (int i = 0; i < 2000 && !someMappingAsksForHugePages(begin, end); ++i) usleep(10000);
    ASSERT_TRUE(someMappingAsksForHugePages(begin, end));
    warmup.finish();
  }
  char* carved = static_cast<char*>(std::malloc(kBlock - kSpan));
  ASSERT_NE(carved, nullptr);
  const auto firstSpan = (reinterpret_cast<std::uintptr_t>(carved) + kSpan - 1) & ~(kSpan - 1);
  std::vector<std::string> spans;
  for (std::uintptr_t at = firstSpan;
       at + kSpan <= reinterpret_cast<std::uintptr_t>(carved) + kBlock - kSpan; at += kSpan)
    spans.push_back(mappingFlags(reinterpret_cast<const char*>(at)));
  std::free(carved);
  ASSERT_GE(spans.size(), 8u);
  // The block's head before its first whole span is shorter than a span: when it is shorter
  // than the megabyte, the first whole span is touched in 4 KiB pages too.
  const std::size_t first = hasFlag(spans[0], "hg") ? 0 : 1;
  EXPECT_TRUE(hasFlag(spans[first], "hg")) << spans[first];
  bool asked = true;
  for (std::size_t i = first; i < spans.size(); ++i) {
    if (!hasFlag(spans[i], "hg")) asked = false;
    if (!asked) {
      EXPECT_FALSE(hasFlag(spans[i], "hg")) << "span " << i << ": " << spans[i];
      EXPECT_TRUE(hasFlag(spans[i], "nh")) << "span " << i << ": " << spans[i];
    }
  }
}

// Once the block is the heap's, the toucher faults in the pages the frame is expected to need,
// up to `neededBytes` from the block's start, without changing a byte: what the frame has
// written there by then stays. The frame's buffer is carved from the freed block's start, which
// only a fresh heap guarantees: the check runs in a process of its own (a death test, re-run
// with only this test), and exits 0 when it holds.
void exitWhetherTheNeededPagesAreFaultedInAndKeepTheirBytes() {
  constexpr std::size_t kBlock = std::size_t{64} << 20;
  constexpr std::size_t kNeeded = std::size_t{40} << 20;
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  MemoryWarmup warmup(kBlock);
  warmup.finish(kNeeded);  // at once: the toucher has reached little of the block
  auto* frame = static_cast<unsigned char*>(std::malloc(kNeeded));
  if (!frame) std::_Exit(2);
  // A byte pattern in the upper half, which the toucher, going up from the block's start,
  // reaches after it has been written.
  constexpr std::size_t kPatternBegin = kNeeded / 2, kPatternEnd = kNeeded - (std::size_t{1} << 20);
  for (std::size_t i = kPatternBegin; i < kPatternEnd; ++i)
    frame[i] = static_cast<unsigned char>(i * 7 + 1);
  // Whole pages of the buffer well within the needed bytes (it starts past the block's start
  // by malloc's header).
  const auto first = (reinterpret_cast<std::uintptr_t>(frame) + page - 1) & ~(page - 1);
  const std::size_t pages = (kNeeded - (std::size_t{1} << 20)) / page;
  std::vector<unsigned char> resident(pages);
  const auto residentPages = [&] {
    // NOLINTNEXTLINE(performance-no-int-to-ptr): the buffer's own pages
    if (mincore(reinterpret_cast<void*>(first), pages * page, resident.data()) != 0)
      return std::size_t{0};
    std::size_t count = 0;
    for (const unsigned char r : resident) count += r & 1u;
    return count;
  };
  // The toucher runs only on an idle core.
  for (int i = 0; i < 6000 && residentPages() < pages; ++i) usleep(10000);
  std::size_t changed = 0;
  for (std::size_t i = kPatternBegin; i < kPatternEnd; ++i)
    changed += frame[i] != static_cast<unsigned char>(i * 7 + 1);
  std::fprintf(stderr, "%zu of %zu pages resident, %zu bytes changed\n", residentPages(), pages,
               changed);
  std::_Exit(residentPages() == pages && changed == 0 ? 0 : 1);
}

TEST(MemoryWarmupDeathTest, AfterFinishTheNeededPagesAreFaultedInAndKeepTheirBytes) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(exitWhetherTheNeededPagesAreFaultedInAndKeepTheirBytes(),
              ::testing::ExitedWithCode(0), "");
}
// Where a fresh 4 KiB page is dear, what the process allocates beside the block, while the scene
// loads (the block still the toucher's) and after the frame outgrows the block, lies in memory
// that asks for huge pages ("hg"); where pages are cheap, it does not. Blocks are carved from the
// heap's top only in a fresh heap: a process of its own, which exits 0 when the check holds.
void exitWhetherTheHeapAboveTheBlockAsksForHugePagesWhereFaultsAreDear() {
  constexpr std::size_t kBlock = std::size_t{16} << 20;
  constexpr std::size_t kLoaded = std::size_t{32} << 20, kOutgrown = std::size_t{64} << 20;
  bool huge = false;
  std::string loaded, outgrown;
  {
    MemoryWarmup warmup(kBlock);
    huge = warmup.heapAbove().hugePages;
    char* texture = static_cast<char*>(std::malloc(kLoaded));
    if (!texture) std::_Exit(2);
    loaded = mappingFlags(texture + kLoaded / 2);
    warmup.finish();
    char* frame = static_cast<char*>(std::malloc(kOutgrown));  // larger than the freed block
    if (!frame) std::_Exit(2);
    outgrown = mappingFlags(frame + kOutgrown / 2);
  }
  std::fprintf(stderr, "huge heap %d\nloaded: %s\noutgrown: %s\n", huge ? 1 : 0, loaded.c_str(),
               outgrown.c_str());
  std::_Exit(hasFlag(loaded, "hg") == huge && hasFlag(outgrown, "hg") == huge ? 0 : 1);
}

TEST(MemoryWarmupDeathTest, TheHeapAboveTheBlockAsksForHugePagesWhereFaultsAreDear) {
  if (!kernelHasHugePages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(exitWhetherTheHeapAboveTheBlockAsksForHugePagesWhereFaultsAreDear(),
              ::testing::ExitedWithCode(0), "");
}
#endif

class MemoryWarmupCliTest : public test_support::CliFixture {
 protected:
  MemoryWarmupCliTest() : CliFixture("omnishadow-memory-warmup") {}
};

TEST_F(MemoryWarmupCliTest, ARenderWritesTheSameImageWithAndWithoutIt) {
  test_support::writeBoxScene(input("scene.gltf"));
  const std::vector<std::string> size = {"--width", "64", "--height", "48"};
  runSucceeding("render", {in("scene.gltf"), "-o", "on.png"}, size);
  const Run off =
      run({"render", in("scene.gltf"), "-o", "off.png", "--width", "64", "--height", "48"},
          {"OMNISHADOW_MEMORY_WARMUP=0"});
  ASSERT_EQ(off.status, 0) << off.err;
  EXPECT_TRUE(sameBytes(output("on.png"), output("off.png")));
}

// A batch's workers inherit the heap its process set up (cli/malloc_heap.h); they draw what
// they drew without it.
TEST_F(MemoryWarmupCliTest, ABatchWritesTheSameImagesWithAndWithoutTheHeapSetUp) {
  test_support::writeBoxScene(input("a/scene.gltf"));
  test_support::writeBoxScene(input("b/scene.gltf"), {.boxX = 0.4f});
  // The folder: its tree is mirrored in the output folder.
  std::vector<std::string> on = {"batch",    in_.string(), "--width", "64",
                                 "--height", "48",         "-q",      "-o"};
  std::vector<std::string> off = on;
  on.push_back("on");
  off.push_back("off");
  const Run withHeap = run(on);
  ASSERT_EQ(withHeap.status, 0) << withHeap.err;
  const Run without = run(off, {"OMNISHADOW_MEMORY_WARMUP=0"});
  ASSERT_EQ(without.status, 0) << without.err;
  for (const char* name : {"a/scene.png", "b/scene.png"})
    EXPECT_TRUE(sameBytes(output("on") / name, output("off") / name)) << name;
}

}  // namespace
}  // namespace omnishadow::cli::memory_warmup_test
