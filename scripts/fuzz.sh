#!/usr/bin/env bash
# Fuzzes the input parsers with libFuzzer: builds tests/fuzz/ into build-fuzz/ with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer, then runs each target for SECONDS (default 60;
# as many targets at once as there are cores) on its corpus in build-fuzz/corpus-<target>/
# (seeded by tests/fuzz/make_corpus.sh, kept and grown between runs). Exits 1 when a fuzzer
# finds a crash, leak, timeout or out-of-memory, after printing the input that triggers it and
# the command that reproduces it.
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
  # The fuzz targets set their own optimization (cmake/Fuzzing.cmake). What they link
  # uninstrumented (the GL passes behind a manifest's render step, never called; the scene
  # library, which a manifest's checks do call) needs no debug information and compiles faster
  # at -O1 than at -O2 (at -O0 the manifest fuzzer ran 2.6 times slower).
  if ! CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -DNDEBUG" -DOMNISHADOW_FUZZ=ON \
      -DOMNISHADOW_BUILD_TESTS=OFF >"$log" 2>&1; then
    cat "$log" >&2
    rm -f "$build/CMakeCache.txt"
    exit 1
  fi
elif ! cmake "$build" >"$log" 2>&1; then
  # A kept folder learns of targets added since it was configured (make knows no others).
  cat "$log" >&2
  exit 1
fi
jobs=$(nproc 2>/dev/null || echo 2)
if ! cmake --build "$build" -j"$jobs" --target fuzz_lights fuzz_gltf fuzz_manifest fuzz_hdr >"$log" 2>&1; then
  cat "$log" >&2
  exit 1
fi
"$root/tests/fuzz/make_corpus.sh" "$build"

# Memory: an input may not make the loader allocate more than 1 GiB at once or 2 GiB in all.
limits=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10)
# One target per core at a time (libFuzzer runs on one thread), each for SECONDS; their reports
# are printed in a fixed order once all have ended.
fuzz_one() {
  local name=$1 target="$build/fuzz_$1" artifacts="$build/artifacts-$1"
  mkdir -p "$artifacts"
  local rc=0
  nice -n 10 "$target" "${limits[@]}" -dict="$root/tests/fuzz/$name.dict" \
    -artifact_prefix="$artifacts/" -max_total_time="$seconds" -print_final_stats=1 \
    "$build/corpus-$name" >"$build/fuzz_$name.log" 2>&1 || rc=$?
  echo "$rc" >"$build/fuzz_$name.status"
}
names=(lights gltf manifest hdr)
for name in "${names[@]}"; do
  rm -f "$build/fuzz_$name.status"
  while (($(jobs -rp | wc -l) >= jobs)); do wait -n || true; done
  fuzz_one "$name" &
done
wait

status=0
for name in "${names[@]}"; do
  target="$build/fuzz_$name"
  run_log="$build/fuzz_$name.log"
  if [[ "$(cat "$build/fuzz_$name.status" 2>/dev/null)" == 0 ]]; then
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
