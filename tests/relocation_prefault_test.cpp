#include "renderer/gl/relocation_prefault.h"

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <link.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/temp_folder.h"

namespace omnishadow::relocation_prefault_test {
namespace {

using Range = RelocationPrefault::Range;
using test_support::TempFolder;

// The page-aligned file part of each writable segment of the library loaded at `base`, as
// dl_iterate_phdr shows it.
std::vector<Range> writableSegments(std::uintptr_t base) {
  struct Query {
    std::uintptr_t base;
    std::vector<Range> ranges;
  } query{base, {}};
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        auto& q = *static_cast<Query*>(data);
        if (info->dlpi_addr != q.base) return 0;
        for (int i = 0; i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& s = info->dlpi_phdr[i];
          if (s.p_type != PT_LOAD || (s.p_flags & PF_W) == 0) continue;
          q.ranges.push_back({(q.base + s.p_vaddr) & ~std::uintptr_t{4095},
                              (q.base + s.p_vaddr + s.p_filesz + 4095) & ~std::uintptr_t{4095}});
        }
        return 1;
      },
      &query);
  return query.ranges;
}

std::uintptr_t loadAddress(void* symbol) {
  Dl_info info{};
  EXPECT_NE(dladdr(symbol, &info), 0);
  return reinterpret_cast<std::uintptr_t>(info.dli_fbase);
}

bool contains(const std::vector<Range>& ranges, const Range& range) {
  for (const Range& r : ranges)
    if (r.begin == range.begin && r.end == range.end) return true;
  return false;
}

// Waits (up to 10 s, for a loaded CI machine) until the watcher has handled `wanted`.
std::vector<Range> populatedOnceSeen(const RelocationPrefault& prefault,
                                     const std::vector<Range>& wanted) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (;;) {
    std::vector<Range> ranges = prefault.populated();
    bool all = true;
    for (const Range& range : wanted) all = all && contains(ranges, range);
    if (all || std::chrono::steady_clock::now() > deadline) return ranges;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Each test loads its own copy of the library: a library loads once per process.
void* loadCopy(const TempFolder& folder, const char* name) {
  const std::filesystem::path copy = folder.path() / name;
  std::filesystem::copy_file(OMNISHADOW_RELOCATED_TABLE_LIBRARY, copy);
  void* handle = dlopen(copy.c_str(), RTLD_NOW | RTLD_LOCAL);
  EXPECT_NE(handle, nullptr) << dlerror();
  return handle;
}

void expectRelocated(void* handle) {
  const auto* text = static_cast<const char*>(dlsym(handle, "omnishadow_relocated_text"));
  const auto* table = static_cast<const char* const*>(dlsym(handle, "omnishadow_relocated_table"));
  const auto* entries =
      static_cast<const std::size_t*>(dlsym(handle, "omnishadow_relocated_entries"));
  const auto* textBytes =
      static_cast<const std::size_t*>(dlsym(handle, "omnishadow_relocated_text_bytes"));
  ASSERT_NE(text, nullptr);
  ASSERT_NE(table, nullptr);
  ASSERT_NE(entries, nullptr);
  ASSERT_NE(textBytes, nullptr);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < *entries; ++i)
    if (table[i] != text + (i * 7919) % *textBytes) ++wrong;
  EXPECT_EQ(*entries, std::size_t{1} << 17);
  EXPECT_EQ(wrong, 0u) << "of " << *entries << " relocated pointers";
}

TEST(RelocationPrefault, PopulatesTheWritableSegmentsOfALibraryLoadedWhileItWatches) {
  const TempFolder folder("relocation-prefault");
  RelocationPrefault prefault;
  void* handle = loadCopy(folder, "librelocated_a.so");
  ASSERT_NE(handle, nullptr);
  const std::vector<Range> segments =
      writableSegments(loadAddress(dlsym(handle, "omnishadow_relocated_table")));
  ASSERT_FALSE(segments.empty());
  const std::vector<Range> populated = populatedOnceSeen(prefault, segments);
  prefault.stop();
  for (const Range& segment : segments)
    EXPECT_TRUE(contains(populated, segment))
        << "segment " << std::hex << segment.begin << "-" << segment.end;
  // The relocated table is one of them: 1 MiB, all of which the loader wrote.
  std::uintptr_t bytes = 0;
  for (const Range& segment : segments) bytes += segment.end - segment.begin;
  EXPECT_GE(bytes, std::uintptr_t{1} << 20);
  expectRelocated(handle);
  dlclose(handle);
}

TEST(RelocationPrefault, LeavesAloneTheLibrariesLoadedBeforeIt) {
  // libstdc++ was relocated when the test started; populating it would only copy pages.
  const std::vector<Range> libstdcxx =
      writableSegments(loadAddress(reinterpret_cast<void*>(&std::terminate)));
  ASSERT_FALSE(libstdcxx.empty());
  const TempFolder folder("relocation-prefault");
  RelocationPrefault prefault;
  void* handle = loadCopy(folder, "librelocated_b.so");
  ASSERT_NE(handle, nullptr);
  const std::vector<Range> populated = populatedOnceSeen(
      prefault, writableSegments(loadAddress(dlsym(handle, "omnishadow_relocated_table"))));
  prefault.stop();
  EXPECT_FALSE(populated.empty());
  for (const Range& segment : libstdcxx) EXPECT_FALSE(contains(populated, segment));
  dlclose(handle);
}

TEST(RelocationPrefault, RacingTheLoaderLeavesEveryRelocationInPlace) {
  // The watcher populates while the loader writes the same pages; ten libraries, so that some
  // land in the middle of a relocation.
  const TempFolder folder("relocation-prefault");
  RelocationPrefault prefault;
  for (int i = 0; i < 10; ++i) {
    void* handle = loadCopy(folder, ("librelocated_race" + std::to_string(i) + ".so").c_str());
    ASSERT_NE(handle, nullptr);
    expectRelocated(handle);
    dlclose(handle);
  }
}

TEST(RelocationPrefault, StopsWhenAsked) {
  RelocationPrefault prefault;
  prefault.stop();
  prefault.stop();  // again, and once more by the destructor: nothing to join
  const TempFolder folder("relocation-prefault");
  void* handle = loadCopy(folder, "librelocated_c.so");
  ASSERT_NE(handle, nullptr);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_TRUE(prefault.populated().empty());
  expectRelocated(handle);
  dlclose(handle);
}

}  // namespace
}  // namespace omnishadow::relocation_prefault_test
