# libFuzzer targets for the input parsers (scripts/fuzz.sh builds and runs them). Off by default:
# configure a separate build folder with CC=clang CXX=clang++ -DOMNISHADOW_FUZZ=ON.
#
# Each target compiles the loader sources it needs itself, with the fuzzing flags, rather than
# linking the project's libraries (those are built without instrumentation). tinygltf is a
# prebuilt shared library and stays uninstrumented; its allocations still go through ASan.
if(NOT OMNISHADOW_FUZZ)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "OMNISHADOW_FUZZ needs clang (-fsanitize=fuzzer): "
                      "configure with CC=clang CXX=clang++ in a fresh build folder")
endif()

set(omnishadow_fuzz_sanitizers -fsanitize=fuzzer,address,undefined)
# -O1 and line tables, as OSS-Fuzz builds its targets (scripts/fuzz.sh configures everything
# else, the uninstrumented libraries, at -O1 without debug information).
set(omnishadow_fuzz_flags ${omnishadow_fuzz_sanitizers} -O1 -gline-tables-only
  # Undefined behaviour is a finding, not a log line.
  -fno-sanitize-recover=all
  -fno-omit-frame-pointer
  # Keep assert() (glm's index checks) and turn on libstdc++'s bounds checks (ABI-neutral).
  -UNDEBUG -D_GLIBCXX_ASSERTIONS)

function(omnishadow_fuzzer name)
  add_executable(${name} ${ARGN})
  target_include_directories(${name} PRIVATE ${CMAKE_SOURCE_DIR})
  target_compile_options(${name} PRIVATE ${omnishadow_fuzz_flags} ${warnings})
  target_link_options(${name} PRIVATE ${omnishadow_fuzz_sanitizers})
  target_link_libraries(${name} PRIVATE glm::glm nlohmann_json::nlohmann_json)
  # Combined units, as the libraries these sources come from (OMNISHADOW_UNITY_BUILD), but
  # larger: the fuzz build is built from nothing, not edited in. fuzz_gltf's 35 files took 101
  # compiler seconds in 2 units against 128 in 5 units of 8.
  set_target_properties(${name} PROPERTIES UNITY_BUILD ${OMNISHADOW_UNITY_BUILD}
                                           UNITY_BUILD_BATCH_SIZE 20)
endfunction()

omnishadow_fuzzer(fuzz_lights
  tests/fuzz/fuzz_lights.cpp
  renderer/scene/light.cpp
  renderer/scene/lights_loader.cpp)

# Every file of the scene library: the loader reaches most of them (decoders, posing, checks),
# and a file added there must not leave the fuzzer unlinkable.
file(GLOB omnishadow_fuzz_scene_sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/renderer/scene/*.cpp)
omnishadow_fuzzer(fuzz_gltf tests/fuzz/fuzz_gltf.cpp ${omnishadow_fuzz_scene_sources})
# libdraco, libmeshoptimizer, libturbojpeg, libdeflate and libwebp stay uninstrumented too
# (Debian's builds); what they are given and what they return is checked by the instrumented
# loader.
target_link_libraries(fuzz_gltf PRIVATE TinyGLTF::TinyGLTF meshoptimizer::meshoptimizer
  PkgConfig::turbojpeg PkgConfig::libdeflate PkgConfig::libwebp)
target_compile_definitions(fuzz_gltf PRIVATE OMNISHADOW_LIBAVIF_SONAME="${OMNISHADOW_LIBAVIF_SONAME}")

# The Radiance HDR decoder (environment panoramas, diff inputs) alone: it needs no library.
omnishadow_fuzzer(fuzz_hdr
  tests/fuzz/fuzz_hdr.cpp
  renderer/output/radiance_hdr_decoder.cpp)

# The manifest reader and the job checks are instrumented; what they call of the renderer's
# libraries (nothing renders) is linked uninstrumented.
omnishadow_fuzzer(fuzz_manifest
  tests/fuzz/fuzz_manifest.cpp
  cli/batch_jobs.cpp
  cli/common_options.cpp
  cli/frame_set.cpp
  cli/render_job.cpp
  cli/shared_scene_loads.cpp)
# render_job.cpp also holds the render step, so the GL passes are linked (never called), and
# the batch's shared loads.
# common_options.cpp names the demo scene (a manifest job without a scene renders it).
target_compile_definitions(fuzz_manifest PRIVATE OMNISHADOW_DEMO_SCENE="${OMNISHADOW_DEMO_SCENE}")
target_link_libraries(fuzz_manifest PRIVATE omnishadow_passes omnishadow_render omnishadow_output
  omnishadow_scene)
