# shellcheck shell=bash
# Sourced by scripts/test-sanitizers.sh and scripts/test-threads.sh.

# configure_instrumented ROOT BUILD OPTION [CMAKE_ARGS...]: configures BUILD with the CMake OPTION
# on (and the arguments after it, each time), at
# -O1 -g1 instead of RelWithDebInfo's -O2 -g: the build takes half the compiler time (most of
# the sanitizer step's time in CI, where nothing is reused from build/), and line tables are all
# that sanitizer stack traces need.
# A configured BUILD is configured again with what it has, so that tests added since are targets
# (cmake --build does not regenerate the build system for a target it does not know yet).
configure_instrumented() {
  local root=$1 build=$2 option=$3 settings=()
  shift 3
  [[ -f "$build/CMakeCache.txt" ]] ||
    settings=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-D$option=ON"
      "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG")
  cmake -S "$root" -B "$build" "${settings[@]}" "$@" \
    >"$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; return 1; }
}

# print_sanitizer_reports SCRIPT DIR: prints every report file in DIR (one per process that
# found something) to stderr under SCRIPT's name; returns 1 when there was any, 0 otherwise.
print_sanitizer_reports() {
  local script=$1 reports=$2 report
  compgen -G "$reports/*" >/dev/null || return 0
  echo "$script: sanitizer reports:" >&2
  for report in "$reports"/*; do
    echo "---- $report" >&2
    cat "$report" >&2
  done
  return 1
}
