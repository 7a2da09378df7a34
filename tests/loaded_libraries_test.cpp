#include "renderer/gl/loaded_libraries.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "renderer/gl/egl_context.h"

namespace omnishadow::loaded_libraries_test {
namespace {

bool isLoaded(const std::string& path) {
  void* handle = ::dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD);
  if (handle == nullptr) return false;
  ::dlclose(handle);
  return true;
}

bool listed(const std::vector<std::string>& names, const std::string& path) {
  return std::find(names.begin(), names.end(), path) != names.end();
}

// One test: a library once kept stays for the rest of the process, so the library that must be
// left alone is tried first.
TEST(LoadedLibraries, KeepsWhatWasLoadedSinceAndNothingLoadedBefore) {
  const std::string library = OMNISHADOW_RELOCATED_TABLE_LIBRARY;
  ASSERT_FALSE(isLoaded(library));

  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << ::dlerror();
  const std::vector<std::string> withIt = loadedLibraries();
  EXPECT_TRUE(listed(withIt, library));
  keepLibrariesLoadedSince(withIt);
  ::dlclose(handle);
  EXPECT_FALSE(isLoaded(library)) << "a library loaded before was kept";
  EXPECT_FALSE(listed(loadedLibraries(), library));

  const std::vector<std::string> withoutIt = loadedLibraries();
  handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << ::dlerror();
  keepLibrariesLoadedSince(withoutIt);
  ::dlclose(handle);
  EXPECT_TRUE(isLoaded(library)) << "a library loaded since was not kept";
  EXPECT_TRUE(listed(loadedLibraries(), library));
}

// Whatever opening the first display loaded (Mesa's driver and LLVM, on llvmpipe) is still
// there after the last context has ended and terminated its display.
TEST(LoadedLibraries, TheGlDriverOutlivesTheLastContext) {
  const std::vector<std::string> before = loadedLibraries();
  std::vector<std::string> withContext;
  {
    const EglContext context(ContextOptions{});
    withContext = loadedLibraries();
  }
  std::vector<std::string> added;
  for (const std::string& name : withContext)
    if (!listed(before, name)) added.push_back(name);
  ASSERT_FALSE(added.empty()) << "opening a display loaded no library";
  const std::vector<std::string> after = loadedLibraries();
  for (const std::string& name : added) EXPECT_TRUE(listed(after, name)) << name << " was unloaded";
}

}  // namespace
}  // namespace omnishadow::loaded_libraries_test
