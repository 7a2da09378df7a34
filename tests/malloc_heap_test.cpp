// malloc's heap as the CLI sets it up for batches and frame sequences (cli/malloc_heap.h): the
// heap's top asks for huge pages exactly where its first fresh pages were dear, and the pictures
// are the same with and without the set-up.
#include "cli/malloc_heap.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/cli_fixture.h"

namespace omnishadow::cli::malloc_heap_test {
namespace {

using test_support::sameBytes;

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
// The VmFlags line of the mapping that holds `address` ("" when none does).
std::string mappingFlags(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    if (std::sscanf(line.c_str(), "%" SCNxPTR "-%" SCNxPTR " ", &begin, &end) == 2)
      inside = begin <= at && at < end;
    else if (inside && line.rfind("VmFlags:", 0) == 0)
      return line;
  }
  return "";
}

bool asksForHugePages(const std::string& vmFlags) {
  return (vmFlags + " ").find(" hg ") != std::string::npos;
}

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
      asksForHugePages(middle) == advice.hugePages && asksForHugePages(last) == advice.hugePages;
  std::_Exit(holds ? 0 : 1);
}

TEST(MallocHeapDeathTest, TheTopAsksForHugePagesExactlyWhereItsFirstPagesWereDear) {
  if (!std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good())
    GTEST_SKIP() << "no transparent huge pages in this kernel";
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

class MallocHeapCliTest : public test_support::CliFixture {
 protected:
  MallocHeapCliTest() : CliFixture("omnishadow-malloc-heap") {}
};

// A batch's workers inherit the heap its process set up; they draw what they drew without it.
TEST_F(MallocHeapCliTest, ABatchWritesTheSameImagesWithAndWithoutIt) {
  test_support::writeBoxScene(input("a/scene.gltf"));
  test_support::writeBoxScene(input("b/scene.gltf"), {.boxX = 0.4f});
  // The folder: its tree is mirrored in the output folder.
  const std::vector<std::string> args = {"batch",    in_.string(), "--width", "64",
                                         "--height", "48",         "-q",      "-o"};
  std::vector<std::string> on = args, off = args;
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
}  // namespace omnishadow::cli::malloc_heap_test
