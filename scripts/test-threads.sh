#!/usr/bin/env bash
# The tests that run our code on more than one thread, built with ThreadSanitizer
# (-DOMNISHADOW_SANITIZE_THREADS=ON) in build-tsan/: the second shadow context's worker
# (renderer/passes/shadow_worker.h), renderers on two threads at once, loading beside the GL
# context, the batch's loaders and encoders, texture decoding, mipmaps on two threads and on the
# upload's mipmap queue, the texture digests, the memory warm-up's toucher, the reference ray
# caster, the light clusters and the lights' shadow draws worked out on several threads, the float
# beauty encoded in bands beside its readback, decoded pictures shared between loads, and the
# worker's maps in frames without a glFinish after the upload. Fails when a test fails or when
# any process, the CLI started by a test included, wrote a report. Extra arguments go to ctest.
#
# Not part of .ci/run (it would take CI past its time limit); run it after changing anything
# that threads share.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# shellcheck source=scripts/lib/sanitizer-build.sh
source "$root/scripts/lib/sanitizer-build.sh"
build="$root/build-tsan"
"$root/scripts/install-deps.sh"

# CTest's tests of whole test files (-DOMNISHADOW_TESTS_PER_FILE=ON: each file's tests in one
# process), and the programs that hold them.
tests=(parallel_shadow_maps_test concurrent_renderers_test steady_frames_test robustness_test
  render_test verify_test batch_test cli_test camera_sets_test material_render_test
  gltf_loader_test jpeg_texture_test png_texture_test image_mipmaps_test mipmap_queue_test
  memory_warmup_test texture_cache_test scene_fingerprint_test view_math_test in_parts_test
  srgb8_band_encoding_test srgb8_beauty_test decoded_image_cache_test pixel_bytes_test
  shared_scene_loads_test stage_finish_test)
programs=(render_tests cli_tests view_tests scene_tests)

reports="$build/tsan-reports"
mkdir -p "$build"
rm -rf "$reports"
mkdir -p "$reports"
# halt_on_error=0: every race of a run is reported, not only the first.
export TSAN_OPTIONS="halt_on_error=0:second_deadlock_stack=1:suppressions=$root/tests/sanitizers/tsan.supp:log_path=$reports/tsan:log_exe_name=1"

start=$SECONDS
configure_instrumented "$root" "$build" OMNISHADOW_SANITIZE_THREADS -DOMNISHADOW_TESTS_PER_FILE=ON
jobs=$(nproc 2>/dev/null || echo 2)
if ! cmake --build "$build" -j"$jobs" --target omnishadow "${programs[@]}" >"$build/build.log" 2>&1; then
  cat "$build/build.log" >&2
  exit 1
fi
built=$SECONDS

# A test not built (its file moved to a program not listed above) fails as "Not Run".
pattern=$(IFS='|'; echo "${tests[*]}")
status=0
(cd "$build" && ctest --output-on-failure -j"$jobs" -R "^($pattern)\$" "$@") || status=$?
end=$SECONDS

print_sanitizer_reports test-threads "$reports" || status=1
echo "test-threads: build $((built - start))s, tests $((end - built))s"
exit "$status"
