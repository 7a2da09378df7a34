#!/usr/bin/env bash
# What the worker process costs: renders N generated small scenes (default 200) with
# `omnishadow batch` (worker process) and `omnishadow batch --in-process`, alternating, ROUNDS
# times each (default 3), and prints every wall time, the medians and their ratio. Not a test:
# numbers only.
# Usage: scripts/bench-batch-worker.sh [N] [ROUNDS]
set -euo pipefail
source "$(dirname "$0")/lib/bench-scenes.sh"
count=${1:-200}
rounds=${2:-3}
make_bench_scenes "$count" 1

seconds() {
  local start
  start=$(date +%s.%N)
  "$@" >/dev/null
  awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f\n", b - a }'
}
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

: >"$work/worker.txt"
: >"$work/inprocess.txt"
for round in $(seq "$rounds"); do
  rm -rf "$work/out"
  seconds "$bin" batch "$work/scenes" --out "$work/out" --width 320 --height 240 --quiet \
    >>"$work/worker.txt"
  rm -rf "$work/out"
  seconds "$bin" batch "$work/scenes" --out "$work/out" --width 320 --height 240 --quiet \
    --in-process >>"$work/inprocess.txt"
done
worker=$(median <"$work/worker.txt")
inprocess=$(median <"$work/inprocess.txt")
printf '%d scenes, 320x240, %d rounds\n' "$count" "$rounds"
printf '  worker process: %s s (median %s)\n' "$(paste -sd' ' "$work/worker.txt")" "$worker"
printf '  --in-process:   %s s (median %s)\n' "$(paste -sd' ' "$work/inprocess.txt")" "$inprocess"
printf '  ratio:          %.3f\n' "$(awk -v a="$worker" -v b="$inprocess" 'BEGIN { print a / b }')"
