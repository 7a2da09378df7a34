#!/usr/bin/env bash
# Renders the demo scene N times (default 5) and prints the median of each --stats stage, the
# median wall time and the median peak RSS from /usr/bin/time -v. Not a test: numbers only.
# Usage: scripts/bench-demo.sh [N] [extra omnishadow render options...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
runs=${1:-5}
shift || true
"$root/scripts/build.sh" omnishadow
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for i in $(seq "$runs"); do
  /usr/bin/time -v "$root/build/omnishadow" render -o "$work/demo.png" --stats "$@" \
    >/dev/null 2>"$work/run$i.log"
done
python3 - "$work" "$runs" <<'PY'
import re, statistics, sys
work, runs = sys.argv[1], int(sys.argv[2])
stages, wall, rss = {}, [], []
for i in range(1, runs + 1):
    text = open(f"{work}/run{i}.log").read()
    for name, ms in re.findall(r"^(\w[\w ]*?)\s+([\d.]+)$", text, re.M):
        stages.setdefault(name, []).append(float(ms))
    m = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", text)
    wall.append(int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3)))
    rss.append(int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)))
print(f"demo scene, {runs} runs, medians")
for name, values in stages.items():
    print(f"  {name:<12} {statistics.median(values):8.1f} ms")
print(f"  {'wall':<12} {statistics.median(wall) * 1000:8.1f} ms  (/usr/bin/time)")
print(f"  {'peak RSS':<12} {statistics.median(rss) / 1024:8.1f} MiB")
PY
