// The render's memory warm-up (cli/memory_warmup.h): what it does to malloc, that it can be
// turned off, and that it changes no output. A test program of its own: malloc's settings are
// the process's.
#include "cli/memory_warmup.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/cli_fixture.h"

namespace omnishadow::cli {
namespace {

using test_support::sameBytes;

#if !defined(__SANITIZE_ADDRESS__)
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

// The flags of the mapping that holds `address`, from /proc/self/smaps ("" when none does).
std::string mappingFlags(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    if (std::sscanf(line.c_str(), "%" SCNxPTR "-%" SCNxPTR " ", &begin, &end) == 2) {
      inside = begin <= at && at < end;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line;
    }
  }
  return "";
}

// The warm block asks for transparent huge pages ("hg" in the mapping's flags: MADV_HUGEPAGE),
// and a cube map's block carved from it after the warm-up lies in such a mapping.
TEST(MemoryWarmup, TheBlockAsksForHugePages) {
  {
    MemoryWarmup warmup(std::size_t{64} << 20);
    warmup.finish();
  }
  char* cubeMap = static_cast<char*>(std::malloc(std::size_t{24} << 20));
  ASSERT_NE(cubeMap, nullptr);
  const std::string flags = mappingFlags(cubeMap + (std::size_t{12} << 20));
  std::free(cubeMap);
  ASSERT_FALSE(flags.empty());
  EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
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

}  // namespace
}  // namespace omnishadow::cli
