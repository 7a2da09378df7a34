#!/usr/bin/env bash
# The tests that run our code on more than one thread, built with ThreadSanitizer
# (-DOMNISHADOW_SANITIZE_THREADS=ON) in build-tsan/: the second shadow context's worker
# (renderer/passes/shadow_worker.h), renderers on two threads at once, loading beside the GL
# context, the batch's loaders and encoders, texture decoding, mipmaps on two threads and on the
# upload's mipmap queue, the texture digests, the memory warm-up's toucher, the reference ray
# caster, the light clusters and the lights' shadow draws worked out on several threads, the float
# beauty encoded in bands beside its readback, decoded pictures shared between loads, and the
# worker's maps in frames without a glFinish after the upload. Fails when a test fails or when
# any process, the CLI started by a test included, wrote a report. Extra arguments go to every
# test program (a second --gtest_filter=... replaces the script's).
#
# Not part of .ci/run (it would take CI past its time limit); run it after changing anything
# that threads share.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# shellcheck source=scripts/lib/sanitizer-build.sh
source "$root/scripts/lib/sanitizer-build.sh"
build="$root/build-tsan"
"$root/scripts/install-deps.sh"

# Each line: a test program, then the test files of it to run (tests/<name>_test.cpp), in one
# process per program.
groups=(
  "render_tests parallel_shadow_maps concurrent_renderers render material_render texture_cache
   srgb8_band_encoding srgb8_beauty shared_scene_loads stage_finish verify"
  "cli_tests steady_frames robustness batch cli memory_warmup"
  "view_tests camera_sets view_math in_parts decoded_image_cache"
  "scene_tests gltf_loader jpeg_texture png_texture image_mipmaps mipmap_queue scene_fingerprint
   pixel_bytes")
programs=()
for group in "${groups[@]}"; do
  read -r -d '' -a words <<<"$group" || true
  programs+=("${words[0]}")
done

# The gtest filter of some test files: the suites they define, as CMake's one-process tests name
# them (tests/CMakeLists.txt), with or without a parameterized prefix.
suites_of() {
  local file suite
  for file in "$@"; do
    sed -nE 's/^(TEST|TEST_F|TEST_P|TYPED_TEST)\( *([A-Za-z0-9_]+).*/\2/p' "$root/tests/${file}_test.cpp"
  done | sort -u | while read -r suite; do printf '%s.*:*/%s.*:' "$suite" "$suite"; done
}

reports="$build/tsan-reports"
mkdir -p "$build"
rm -rf "$reports"
mkdir -p "$reports"
# halt_on_error=0: every race of a run is reported, not only the first.
export TSAN_OPTIONS="halt_on_error=0:second_deadlock_stack=1:suppressions=$root/tests/sanitizers/tsan.supp:log_path=$reports/tsan:log_exe_name=1"

start=$SECONDS
configure_instrumented "$root" "$build" OMNISHADOW_SANITIZE_THREADS
jobs=$(nproc 2>/dev/null || echo 2)
if ! cmake --build "$build" -j"$jobs" --target omnishadow "${programs[@]}" >"$build/build.log" 2>&1; then
  cat "$build/build.log" >&2
  exit 1
fi
built=$SECONDS

# Left out: the tests that make a batch worker crash on purpose (a fault-injection library raises
# SIGSEGV in it). ThreadSanitizer handles that signal itself and prints its own report instead of
# the crash the batch is checked to survive.
crashes="RobustnessTest.BatchGoesOnAfterAWorkerCrashOrHang:RobustnessTest.BatchGivesUpOnAWorkerThatDiesBeforeAnyJob"
status=0
for group in "${groups[@]}"; do
  read -r -d '' -a words <<<"$group" || true
  program=${words[0]}
  suites=$(suites_of "${words[@]:1}")
  filter="${suites%:}-$crashes"
  if ! (cd "$build/tests" && "./$program" "--gtest_filter=$filter" "$@" >"$build/$program.log" 2>&1); then
    echo "test-threads: $program failed:" >&2
    grep -E '^\[  FAILED  \]' "$build/$program.log" >&2 || tail -20 "$build/$program.log" >&2
    status=1
  fi
done
end=$SECONDS

print_sanitizer_reports test-threads "$reports" || status=1
echo "test-threads: build $((built - start))s, tests $((end - built))s"
exit "$status"
