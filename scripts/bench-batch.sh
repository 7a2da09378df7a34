#!/usr/bin/env bash
# Renders N generated small scenes (default 200) twice, side by side: once as one
# `omnishadow batch` and once as N separate `omnishadow render` processes; prints both wall
# times and their ratio. Not a test: numbers only.
# Usage: scripts/bench-batch.sh [N] [SEED]
set -euo pipefail
source "$(dirname "$0")/lib/bench-scenes.sh"
count=${1:-200}
make_bench_scenes "$count" "${2:-1}"
size=(--width 320 --height 240)

start=$(date +%s.%N)
"$bin" batch "$work/scenes" --out "$work/batch" "${size[@]}" --quiet
batch=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

start=$(date +%s.%N)
for scene in "$work"/scenes/*.glb; do
  name=$(basename "$scene" .glb)
  "$bin" render "$scene" -o "$work/single/$name.png" "${size[@]}" >/dev/null
done
single=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

# Same pixels either way.
if ! cmp -s <(cd "$work/batch" && find . -name '*.png' | sort | xargs cat) \
            <(cd "$work/single" && find . -name '*.png' | sort | xargs cat); then
  echo "warning: batch and single renders differ" >&2
fi
printf '%d scenes, 320x240, two 256^2 shadowed point lights each\n' "$count"
printf '  one batch:            %7.2f s\n' "$batch"
printf '  %d render processes: %7.2f s\n' "$count" "$single"
printf '  ratio:                %7.1fx\n' "$(awk -v a="$single" -v b="$batch" 'BEGIN { print a / b }')"
