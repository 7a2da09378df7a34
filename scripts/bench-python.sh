#!/usr/bin/env bash
# Renders N generated small scenes (default 100) through the Python module and as one
# `omnishadow batch` (with its worker threads, and with --jobs 0, everything on one thread like
# the Python loop), side by side, each writing one PNG per scene; prints the renders per second,
# the ratios and the peak memory (max RSS) of each. The Python loop runs twice: as it is, and
# after omnishadow.use_rendering_heap() (malloc's heap set up as batch has it). Not a test:
# numbers only.
# Usage: [ROUNDS=3] [SIZE=320x240] [SCENES=DIR] scripts/bench-python.sh [N] [SEED]
#        [extra options for both, e.g. --aa 4]
# SCENES=DIR renders DIR's .glb files instead (each with NAME.lights.json beside it), N ignored.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
count=${1:-100}
seed=${2:-1}
shift $(($# < 2 ? $# : 2))
"$root/scripts/build.sh" omnishadow omnishadow_python make_bench_scenes
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [[ -n "${SCENES:-}" ]]; then
  mkdir "$work/scenes"
  cp "$SCENES"/*.glb "$SCENES"/*.lights.json "$work/scenes/"
  count=$(find "$work/scenes" -name '*.glb' | wc -l)
else
  "$root/build/make_bench_scenes" "$work/scenes" "$count" "$seed"
fi
bin="$root/build/omnishadow"

# Prints "<seconds> <max RSS KiB>" of a command.
measure() {
  /usr/bin/time -f '%e %M' -o "$work/time" "$@" >/dev/null
  cat "$work/time"
}

size=${SIZE:-320x240}
width=${size%x*} height=${size#*x}
aa=1
for ((i = 1; i <= $#; i++)); do [[ "${!i}" == --aa ]] && { j=$((i + 1)); aa=${!j}; }; done
# Rounds alternate between the four, so that the machine's load hits them alike; medians.
rounds=${ROUNDS:-3}
: >"$work/runs"
for ((r = 0; r < rounds; r++)); do
  rm -rf "$work/batch" "$work/batch0"
  echo "batch $(measure "$bin" batch "$work/scenes" --out "$work/batch" --width "$width" \
    --height "$height" --quiet "$@")" >>"$work/runs"
  echo "batch0 $(measure "$bin" batch "$work/scenes" --out "$work/batch0" --width "$width" \
    --height "$height" --quiet --jobs 0 "$@")" >>"$work/runs"
  for heap in 0 1; do
    rm -rf "$work/python$heap"
    echo "python$heap $(measure env PYTHONPATH="$root/build/python" /usr/bin/python3 -c '
import sys, pathlib, omnishadow
scenes, out, aa, heap = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4] == "1"
w, h = int(sys.argv[5]), int(sys.argv[6])
if heap:
    omnishadow.use_rendering_heap()
out.mkdir()
renderer = omnishadow.Renderer()
for path in sorted(scenes.glob("*.glb")):
    scene = omnishadow.load_scene(path)
    frame = renderer.render(scene, path.with_suffix(".lights.json"), width=w, height=h, aa=aa)
    frame.save(out / (path.stem + ".png"))
' "$work/scenes" "$work/python$heap" "$aa" "$heap" "$width" "$height")" >>"$work/runs"
  done
done
median() { awk -v k="$1" -v f="$2" '$1 == k { print $f }' "$work/runs" | sort -g |
  awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
batch=$(median batch 2) batch_rss=$(median batch 3)
batch0=$(median batch0 2) batch0_rss=$(median batch0 3)
python=$(median python0 2) python_rss=$(median python0 3)
python_heap=$(median python1 2) python_heap_rss=$(median python1 3)

for heap in 0 1; do
  if ! cmp -s <(cd "$work/batch" && find . -name '*.png' | sort | xargs cat) \
              <(cd "$work/python$heap" && find . -name '*.png' | sort | xargs cat); then
    echo "warning: batch and Python renders differ (python$heap)" >&2
  fi
done
rate() { awk -v n="$count" -v s="$1" 'BEGIN { printf "%.2f", n / s }'; }
printf '%d scenes (%s), %s %s; medians of %d rounds\n' "$count" \
  "${SCENES:-generated, two shadowed point lights each}" "$size" "$*" "$rounds"
printf '  batch (workers):     %7.2f s  %6s renders/s  max RSS %6d KiB\n' "$batch" "$(rate "$batch")" "$batch_rss"
printf '  batch --jobs 0:      %7.2f s  %6s renders/s  max RSS %6d KiB\n' "$batch0" "$(rate "$batch0")" "$batch0_rss"
printf '  python (one thread): %7.2f s  %6s renders/s  max RSS %6d KiB\n' "$python" "$(rate "$python")" "$python_rss"
printf '  python, rendering heap:%5.2f s  %6s renders/s  max RSS %6d KiB\n' "$python_heap" "$(rate "$python_heap")" "$python_heap_rss"
printf '  python / batch --jobs 0 time: %.3f\n' "$(awk -v a="$python" -v b="$batch0" 'BEGIN { print a / b }')"
