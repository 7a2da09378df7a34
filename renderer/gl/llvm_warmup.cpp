#include "renderer/gl/llvm_warmup.h"

#include <dlfcn.h>
#include <pthread.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "renderer/core/under_valgrind.h"

namespace omnishadow {
namespace {

// The few entries of LLVM's C API (llvm-c/Core.h, llvm-c/ExecutionEngine.h) the warm-up calls,
// looked up in the library the driver loaded: omnishadow does not link LLVM. Their references
// are pointers to opaque structs and LLVMBool an int, the same in every LLVM since 3.x.
using Ref = void*;
struct McjitOptions {  // LLVMMCJITCompilerOptions
  unsigned optLevel;
  int codeModel;
  int noFramePointerElim;
  int enableFastIsel;
  Ref memoryManager;
};

struct LlvmApi {
  Ref (*contextCreate)();
  void (*contextDispose)(Ref);
  Ref (*moduleCreate)(const char*, Ref);
  Ref (*int32Type)(Ref);
  Ref (*functionType)(Ref, Ref*, unsigned, int);
  Ref (*addFunction)(Ref, const char*, Ref);
  Ref (*appendBlock)(Ref, Ref, const char*);
  Ref (*createBuilder)(Ref);
  void (*positionAtEnd)(Ref, Ref);
  Ref (*buildRet)(Ref, Ref);
  Ref (*constInt)(Ref, unsigned long long, int);
  void (*disposeBuilder)(Ref);
  void (*linkInMcjit)();
  void (*initializeMcjitOptions)(McjitOptions*, std::size_t);
  int (*createMcjit)(Ref*, Ref, McjitOptions*, std::size_t, char**);
  std::uint64_t (*functionAddress)(Ref, const char*);
  void (*disposeEngine)(Ref);
  void (*disposeMessage)(char*);

  // False where a symbol is missing (then nothing is called).
  bool load(void* library) {
    bool all = true;
    const auto find = [&](auto& entry, const char* name) {
      entry = reinterpret_cast<std::remove_reference_t<decltype(entry)>>(dlsym(library, name));
      all = all && entry != nullptr;
    };
    find(contextCreate, "LLVMContextCreate");
    find(contextDispose, "LLVMContextDispose");
    find(moduleCreate, "LLVMModuleCreateWithNameInContext");
    find(int32Type, "LLVMInt32TypeInContext");
    find(functionType, "LLVMFunctionType");
    find(addFunction, "LLVMAddFunction");
    find(appendBlock, "LLVMAppendBasicBlockInContext");
    find(createBuilder, "LLVMCreateBuilderInContext");
    find(positionAtEnd, "LLVMPositionBuilderAtEnd");
    find(buildRet, "LLVMBuildRet");
    find(constInt, "LLVMConstInt");
    find(disposeBuilder, "LLVMDisposeBuilder");
    find(linkInMcjit, "LLVMLinkInMCJIT");
    find(initializeMcjitOptions, "LLVMInitializeMCJITCompilerOptions");
    find(createMcjit, "LLVMCreateMCJITCompilerForModule");
    find(functionAddress, "LLVMGetFunctionAddress");
    find(disposeEngine, "LLVMDisposeExecutionEngine");
    find(disposeMessage, "LLVMDisposeMessage");
    return all;
  }
};

constexpr int kAnswer = 42;

// Compiles `int warmup() { return 42; }` to machine code as llvmpipe compiles its functions
// (MCJIT, the default optimization level) and runs it. The native target is the one the driver
// initialized when it loaded: where it did not, MCJIT refuses and nothing was compiled.
bool compileOnce(const LlvmApi& llvm) {
  llvm.linkInMcjit();
  Ref context = llvm.contextCreate();
  Ref module = llvm.moduleCreate("omnishadow_warmup", context);
  Ref int32 = llvm.int32Type(context);
  Ref function = llvm.addFunction(module, "warmup", llvm.functionType(int32, nullptr, 0, 0));
  Ref builder = llvm.createBuilder(context);
  llvm.positionAtEnd(builder, llvm.appendBlock(context, function, "entry"));
  llvm.buildRet(builder, llvm.constInt(int32, kAnswer, 0));
  llvm.disposeBuilder(builder);

  McjitOptions options{};
  llvm.initializeMcjitOptions(&options, sizeof options);
  options.optLevel = 2;
  Ref engine = nullptr;
  char* error = nullptr;
  bool ran = false;
  if (llvm.createMcjit(&engine, module, &options, sizeof options, &error) == 0) {
    // The engine owns the module from here on.
    const std::uint64_t address = llvm.functionAddress(engine, "warmup");
    // NOLINTNEXTLINE(performance-no-int-to-ptr): the address of the function just compiled
    ran = address != 0 && reinterpret_cast<int (*)()>(address)() == kAnswer;
    llvm.disposeEngine(engine);
  } else if (error) {
    llvm.disposeMessage(error);
  }
  llvm.contextDispose(context);
  return ran;
}

}  // namespace

std::string LlvmWarmup::llvmLibrary(const std::vector<std::string>& libraries) {
  for (const std::string& path : libraries) {
    const std::size_t slash = path.find_last_of('/');
    const std::string name = path.substr(slash == std::string::npos ? 0 : slash + 1);
    if (name.rfind("libLLVM", 0) == 0 && name.find(".so") != std::string::npos) return path;
  }
  return {};
}

LlvmWarmup::LlvmWarmup(const std::vector<std::string>& libraries) {
  if (underValgrind()) return;  // one thread at a time there: it would only compete
  const std::string library = llvmLibrary(libraries);
  if (library.empty()) return;
  thread_ = std::thread([this, library] {
    pthread_setname_np(pthread_self(), "omni-llvm-warm");
    // Already loaded by the driver: this only takes a reference, given back at the end.
    void* handle = dlopen(library.c_str(), RTLD_LAZY | RTLD_NOLOAD);
    if (!handle) return;
    LlvmApi llvm{};
    compiled_ = llvm.load(handle) && compileOnce(llvm);
    dlclose(handle);
  });
}

LlvmWarmup::~LlvmWarmup() {
  wait();
}

bool LlvmWarmup::wait() {
  if (thread_.joinable()) {
    thread_.join();
    finished_ = true;
  }
  return compiled_;
}

}  // namespace omnishadow
