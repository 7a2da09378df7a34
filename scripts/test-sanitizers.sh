#!/usr/bin/env bash
# The whole test suite built with AddressSanitizer + UndefinedBehaviorSanitizer
# (-DOMNISHADOW_SANITIZE=ON) in build-asan/. Installs what is missing, builds quietly (the log is
# printed only when the build fails), runs CTest (a test per test file, its tests in one process;
# extra arguments go to ctest), and fails when a test fails or when any process, the CLI started
# by a test included, wrote a sanitizer report.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# shellcheck source=scripts/lib/sanitizer-build.sh
source "$root/scripts/lib/sanitizer-build.sh"
build="$root/build-asan"
supp="$root/tests/sanitizers"
"$root/scripts/install-deps.sh"

# Reports go to files, one per process (<reports>/asan.<program>.<pid>, ubsan.<program>.<pid>):
# a test that runs the CLI and reads its stderr, or expects it to fail, still cannot hide one;
# they are printed at the end.
reports="$build/sanitizer-reports"
mkdir -p "$build"
rm -rf "$reports"
mkdir -p "$reports"

# halt_on_error, exitcode: the first finding ends the process with a status no test expects.
# detect_leaks: LeakSanitizer at exit (lsan.supp is for the platform's own one-off leaks).
# quarantine_size_mb: freed memory is kept poisoned (to catch use after free) up to this much;
# the default 256 MiB fills only after a few hundred renders, which a test that checks that
# 1000 renders in one context do not grow the resident memory would take for a leak.
asan="detect_leaks=1:halt_on_error=1:abort_on_error=0:exitcode=86:quarantine_size_mb=64"
asan+=":check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1"
# intercept_tls_get_addr=0: GCC 12's runtime takes a dynamic TLS block that malloc happened to
# place at a certain page offset for a pre-2.25 glibc header and reads the words before it, and
# LeakSanitizer's tracer then dies at exit (SIGSEGV, "LeakSanitizer has encountered a fatal
# error"; fixed after GCC 13 and LLVM 16). Mesa's driver, loaded with dlopen, has such TLS: 3 of
# the CLI's tests met it. The blocks stay scanned without the interceptor: glibc allocates them
# with malloc, and each thread's static TLS, which LeakSanitizer scans, points at them.
asan+=":intercept_tls_get_addr=0"
export ASAN_OPTIONS="$asan:log_path=$reports/asan:log_exe_name=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=87:suppressions=$supp/ubsan.supp:log_path=$reports/ubsan:log_exe_name=1"

start=$SECONDS
# Each test file's tests in one process (a CTest test per file): under the sanitizers a process's
# start (0.1 s) and a renderer's set-up cost several times what they cost uninstrumented, and the
# suite's own step already runs each test alone. A report names the process, and the gtest output
# beside it the test.
configure_instrumented "$root" "$build" OMNISHADOW_SANITIZE -DOMNISHADOW_TESTS_PER_FILE=ON
jobs=$(nproc 2>/dev/null || echo 2)
if ! cmake --build "$build" -j"$jobs" >"$build/build.log" 2>&1; then
  cat "$build/build.log" >&2
  cat "$reports"/* >&2 2>/dev/null || true
  exit 1
fi
built=$SECONDS

status=0
(cd "$build" && ctest --output-on-failure -j"$jobs" "$@") || status=$?
end=$SECONDS

print_sanitizer_reports test-sanitizers "$reports" || status=1
echo "test-sanitizers: build $((built - start))s, tests $((end - built))s"
exit "$status"
