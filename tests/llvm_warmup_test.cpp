#include "renderer/gl/llvm_warmup.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "renderer/gl/egl_context.h"
#include "renderer/gl/loaded_libraries.h"

namespace omnishadow::llvm_warmup_test {
namespace {

TEST(LlvmWarmup, TellsLlvmsLibraryByItsFileName) {
  EXPECT_EQ(LlvmWarmup::llvmLibrary({"/lib/x86_64-linux-gnu/libc.so.6",
                                     "/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1",
                                     "/usr/lib/libLLVM.so.18.1"}),
            "/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1");
  EXPECT_EQ(LlvmWarmup::llvmLibrary({"libLLVM.so.18.1"}), "libLLVM.so.18.1");
  EXPECT_EQ(LlvmWarmup::llvmLibrary(
                {"/usr/lib/libLLVMSupport.a", "/opt/libllvm.so.1", "/opt/libLLVM-15/libc.so.6"}),
            "");
  EXPECT_EQ(LlvmWarmup::llvmLibrary({}), "");
}

TEST(LlvmWarmup, StartsNothingWhereNoLlvmWasLoaded) {
  LlvmWarmup warmup({"/lib/x86_64-linux-gnu/libc.so.6", "/lib/x86_64-linux-gnu/libm.so.6"});
  EXPECT_FALSE(warmup.started());
  EXPECT_FALSE(warmup.wait());
}

TEST(LlvmWarmup, CompilesNothingWithAnLlvmThatIsNotLoaded) {
  // Only a library the driver has loaded is used: the warm-up loads nothing itself.
  LlvmWarmup warmup({"/nonexistent/libLLVM-99.so.1"});
  EXPECT_FALSE(warmup.wait());
}

TEST(LlvmWarmup, CompilesAndRunsAFunctionWithTheLlvmTheDriverLoaded) {
  const EglContext context(ContextOptions{});  // llvmpipe brings LLVM
  const std::string llvm = LlvmWarmup::llvmLibrary(loadedLibraries());
  if (llvm.empty()) GTEST_SKIP() << "this GL driver uses no LLVM";
  LlvmWarmup warmup(loadedLibraries());
  EXPECT_TRUE(warmup.started());
  EXPECT_TRUE(warmup.wait()) << "the function compiled with " << llvm << " did not return 42";
  // The driver still compiles and draws after it (its own LLVM contexts, the same library).
}

// In a process of its own: only the context whose display loaded LLVM can start the warm-up,
// and only when asked, once.
TEST(LlvmWarmupDeathTest, OnlyTheContextThatLoadedLlvmStartsItWhenAsked) {
  // Each child runs the test program anew, in which no display was opened yet.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        EglContext first{ContextOptions{}};
        // A driver without LLVM (a GPU's) has nothing to warm up.
        if (LlvmWarmup::llvmLibrary(loadedLibraries()).empty())
          std::exit(!first.startLlvmWarmup() && first.llvmWarmup() == nullptr ? 0 : 3);
        if (first.llvmWarmup() != nullptr) std::exit(1);  // not before it is asked
        // A second context on the same display loaded nothing: it has nothing to start.
        EglContext second{ContextOptions{}};
        if (second.startLlvmWarmup() || second.llvmWarmup() != nullptr) std::exit(4);
        first.makeCurrent();
        if (!first.startLlvmWarmup()) std::exit(5);
        LlvmWarmup* warmup = first.llvmWarmup();
        if (warmup == nullptr || !first.startLlvmWarmup() || first.llvmWarmup() != warmup)
          std::exit(6);  // asked again: the same one
        std::exit(warmup->wait() ? 0 : 2);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace omnishadow::llvm_warmup_test
