#!/usr/bin/env bash
# omnishadow against three.js r187 in headless Chromium on the same rasterizer (issue 19):
# process time, first frame and steady-state frame on Box, cornell-box, Sundial, WhackAMole and
# test_room, interleaved, medians. Runs ../shared/peers/compare.py's runners through
# scripts/bench_peers.py; installs the harness's dependencies the way its setup.sh does.
#
# Usage: scripts/bench-peers.sh [--rounds N] [--repeat N] [--scenes a,b] [--bin FILE]
#                               [--baseline FILE] [--peers DIR] [--out DIR] [--no-doc]
# --bin FILE       the omnishadow to measure (default: build/omnishadow, built by scripts/build.sh)
# --baseline FILE  another binary measured in the same rounds (before/after columns; the
#                  rounds are raised to an even number, so that each binary runs right after
#                  three.js equally often)
# --peers DIR      the peers folder (default: ../shared/peers beside the repository)
# --out DIR        where peers.md goes (default build-bench/peers)
# --no-doc         do not write the table into docs/performance.md (between the
#                  "bench-peers:begin/end" markers)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rounds=3 repeat=10 scenes=box,cornell,sundial,whackamole,test_room bin="" baseline=""
peers="$root/../shared/peers" out="$root/build-bench/peers" doc=1
while (($#)); do
  case $1 in
    --rounds) rounds=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --scenes) scenes=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --baseline) baseline=$2; shift 2 ;;
    --peers) peers=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --no-doc) doc=0; shift ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) echo "bench-peers: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ -f "$peers/compare.py" ]] || { echo "bench-peers: no compare.py in $peers (--peers DIR)" >&2; exit 2; }
if [[ -z "$bin" ]]; then
  "$root/scripts/build.sh" omnishadow
  bin="$root/build/omnishadow"
fi
# The harness's dependencies, as its setup.sh installs them: Debian's chromium and the pinned
# npm packages.
if [[ ! -x /usr/lib/chromium/chromium || ! -d "$peers/threejs/node_modules" ]]; then
  sh "$peers/threejs/setup.sh"
fi
args=(--bin "$bin" --peers "$peers" --rounds "$rounds" --repeat "$repeat" --scenes "$scenes" --out "$out")
[[ -n "$baseline" ]] && args+=(--baseline "$baseline")
python3 "$root/scripts/bench_peers.py" "${args[@]}"
if ((doc)); then
  python3 - "$root/docs/performance.md" "$out/peers.md" <<'PY'
import sys
doc, table = sys.argv[1], open(sys.argv[2]).read()
text = open(doc).read()
begin, end = "<!-- bench-peers:begin -->", "<!-- bench-peers:end -->"
if begin in text and end in text:
    text = text[: text.index(begin) + len(begin)] + "\n" + table + text[text.index(end):]
else:
    text += f"\n## Against three.js (scripts/bench-peers.sh)\n\n{begin}\n{table}{end}\n"
open(doc, "w").write(text)
PY
  echo "bench-peers: table written to docs/performance.md" >&2
fi
