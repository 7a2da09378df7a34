#include "renderer/gl/llvm_warmup.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace omnishadow::llvm_warmup_test
