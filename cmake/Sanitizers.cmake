# AddressSanitizer + UndefinedBehaviorSanitizer for every target of the project (library,
# CLI, scene builders, tests), switched on with -DOMNISHADOW_SANITIZE=ON (the option is in the
# root CMakeLists.txt). Use a build folder of its own (scripts/test-sanitizers.sh uses
# build-asan/): instrumented objects must not mix with a normal build's.
#
# ThreadSanitizer, -DOMNISHADOW_SANITIZE_THREADS=ON, instead (the two cannot share a process;
# scripts/test-threads.sh uses build-tsan/).
#
# Included from the root CMakeLists.txt before any target is defined, so that the directory-wide
# add_compile_options/add_link_options reach every target, tests/ included.
if(OMNISHADOW_SANITIZE)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    message(FATAL_ERROR "OMNISHADOW_SANITIZE needs GCC or Clang (got ${CMAKE_CXX_COMPILER_ID})")
  endif()
  # float-cast-overflow (a float out of an integer's range, NaN included, converted to it) is UB
  # that GCC's -fsanitize=undefined leaves out; sizes and indices read from JSON go through it.
  set(omnishadow_sanitizers address,undefined,float-cast-overflow)
  set(omnishadow_sanitize_flags
    -fsanitize=${omnishadow_sanitizers}
    # Every UBSan finding is an error: stop at the first one instead of printing and going on.
    -fno-sanitize-recover=undefined,float-cast-overflow
    # Readable stacks in reports (ASan's fast unwinder follows frame pointers).
    -fno-omit-frame-pointer
    -fno-optimize-sibling-calls)
  add_compile_options(${omnishadow_sanitize_flags})
  add_link_options(-fsanitize=${omnishadow_sanitizers})
  # Executables at a fixed address: in a position-independent one, each instrumented global's
  # ASan descriptor and UBSan type record holds pointers that the loader relocates at every
  # start (1.1 million relocations in the CLI, 335,000 in cli_test), each first write to a page
  # a fault; the suite starts over 1,000 test processes and more CLI runs. The CLI's --version
  # took 0.25 s against 0.14. The same checks either way; the CLI users get stays a PIE.
  add_link_options("$<$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>:-no-pie>")
  message(STATUS "omnishadow: building with AddressSanitizer and UndefinedBehaviorSanitizer")
endif()

if(OMNISHADOW_SANITIZE_THREADS)
  if(OMNISHADOW_SANITIZE)
    message(FATAL_ERROR "OMNISHADOW_SANITIZE and OMNISHADOW_SANITIZE_THREADS exclude each other")
  endif()
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    message(FATAL_ERROR "OMNISHADOW_SANITIZE_THREADS needs GCC or Clang (got ${CMAKE_CXX_COMPILER_ID})")
  endif()
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
  message(STATUS "omnishadow: building with ThreadSanitizer")
endif()

# Whether this build is instrumented at all: what the root CMakeLists.txt tests to build the
# CLI at -O0, leave out the generators and the Python module.
if(OMNISHADOW_SANITIZE OR OMNISHADOW_SANITIZE_THREADS)
  set(OMNISHADOW_INSTRUMENTED ON)
else()
  set(OMNISHADOW_INSTRUMENTED OFF)
endif()
