#!/usr/bin/env bash
# Fuzzes the input parsers with libFuzzer: builds tests/fuzz/ into build-fuzz/ with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer, then runs each target for SECONDS (default 60)
# on its corpus in build-fuzz/corpus-<target>/ (seeded by tests/fuzz/make_corpus.sh, kept and
# grown between runs). Exits 1 when a fuzzer finds a crash, leak, timeout or out-of-memory, after
# printing the input that triggers it and the command that reproduces it.
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
[[ "$seconds" =~ ^[1-9][0-9]*$ ]] || { echo "usage: scripts/fuzz.sh [SECONDS]" >&2; exit 2; }
build="$root/build-fuzz"

"$root/scripts/install-deps.sh"

# Quiet unless something fails, like scripts/build.sh.
log="$build/build.log"
mkdir -p "$build"
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  if ! CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DOMNISHADOW_FUZZ=ON -DOMNISHADOW_BUILD_TESTS=OFF >"$log" 2>&1; then
    cat "$log" >&2
    rm -f "$build/CMakeCache.txt"
    exit 1
  fi
fi
jobs=$(nproc 2>/dev/null || echo 2)
if ! cmake --build "$build" -j"$jobs" --target fuzz_lights fuzz_gltf fuzz_manifest >"$log" 2>&1; then
  cat "$log" >&2
  exit 1
fi
"$root/tests/fuzz/make_corpus.sh" "$build"

# Memory: an input may not make the loader allocate more than 1 GiB at once or 2 GiB in all.
limits=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10)
status=0
for name in lights gltf manifest; do
  target="$build/fuzz_$name"
  artifacts="$build/artifacts-$name"
  mkdir -p "$artifacts"
  run_log="$build/fuzz_$name.log"
  options=("${limits[@]}" -dict="$root/tests/fuzz/$name.dict" -artifact_prefix="$artifacts/")
  if nice -n 10 "$target" "${options[@]}" -max_total_time="$seconds" -print_final_stats=1 \
      "$build/corpus-$name" >"$run_log" 2>&1; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$run_log")
    speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$run_log")
    files=$(find "$build/corpus-$name" -type f | wc -l)
    echo "fuzz_$name: ${seconds} s, ${runs:-?} inputs (${speed:-?}/s), corpus $files files, no crash"
  else
    status=1
    tail -n 60 "$run_log" >&2
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$run_log" | tail -n 1)
    echo >&2
    echo "fuzz_$name FOUND A PROBLEM (full log: $run_log)" >&2
    if [[ -n "$artifact" ]]; then
      echo "  input:     $artifact" >&2
      echo "  reproduce: $target ${limits[*]} $artifact" >&2
    fi
  fi
done
exit "$status"
