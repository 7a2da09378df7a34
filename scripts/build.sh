#!/usr/bin/env bash
# Installs missing packages, configures (once) and builds into build/. Arguments are targets.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
if [[ ! -f "$root/build/CMakeCache.txt" ]]; then
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
jobs=$(nproc 2>/dev/null || echo 2)
targets=()
for t in "$@"; do targets+=(--target "$t"); done
# Quiet unless something fails: make prints errors on stderr, and progress goes to a log.
log="$root/build/build.log"
if ! cmake --build "$root/build" -j"$jobs" "${targets[@]}" >"$log" 2>&1; then
  cat "$log" >&2
  exit 1
fi
