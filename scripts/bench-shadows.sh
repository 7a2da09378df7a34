#!/usr/bin/env bash
# Shadow benchmarks (issue 6; see docs/performance.md). Not a test: numbers only.
#
# Usage: scripts/bench-shadows.sh [SCENARIO...] [--runs N] [--quick] [--out DIR]
#            [--build-dir DIR | --bin OMNISHADOW] [--seed S] [--range auto|none|METERS]
#            [--lights-per-point K] [--timeout SECONDS] [--keep-scenes] [--report-only]
#
# SCENARIO (default: all four, in this order)
#   strategies (1)  250k-triangle room, 4 point lights at 1024^2, once per --shadow-pass
#                   strategy (six, geometry, instanced, auto), with each one's shadow time
#                   relative to `geometry`; only the default pass when the binary lacks the option
#   lights     (2)  the same room with 1, 4, 16, 64, 256 point lights at 512^2
#   triangles  (3)  10k, 50k, 250k, 1M, 2M triangles, 4 lights at 1024^2
#   resolution (4)  cube maps of 256, 512, 1024, 2048, 4096 texels, 4 lights
# --runs N          rounds per configuration (default 5; 1 with --quick). Rounds are
#                   interleaved (A, B, C, A, B, C, ...) and the tables show medians.
# --warmup N        untimed renders of a scenario's first configuration before its rounds
#                   (default 1): the first process after the scenes are written runs cold.
# --quick           smoke test: smaller scenes and cube maps, 640x360, one run each (minutes).
# --out DIR         where shadows.csv (one row per run), summary.md and bench-shadows.png go
#                   (default build-bench/results).
# --build-dir DIR   build a Release omnishadow and the scene generator in DIR instead of using
#                   scripts/build.sh (which builds build/).
# --bin FILE        benchmark this omnishadow binary (e.g. one built elsewhere or on a GPU
#                   machine); the scene generator is still built.
# --seed S          scene seed (default 1). --range and --lights-per-point go to the generator:
#                   auto (default) gives each light a range reaching about K (default 8) lights
#                   per point of the room once there are more than K lights.
# --report-only     no runs: redo summary.md and the plot from DIR/shadows.csv (--out DIR).
#
# Needs /usr/bin/time (package `time`) and python3; installs gnuplot-nox for the plot when it is
# missing (like scripts/install-deps.sh does, but only here: building and testing do not need it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
printf -v command '%q ' scripts/bench-shadows.sh "$@"

out="$root/build-bench/results"
build_dir=""
bin=""
pass=()
scenarios=()
report_only=0
while (($#)); do
  case "$1" in
    --out) out=$2; shift 2 ;;
    --build-dir) build_dir=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --runs|--warmup|--seed|--range|--lights-per-point|--timeout) pass+=("$1" "$2"); shift 2 ;;
    --quick|--keep-scenes) pass+=("$1"); shift ;;
    --report-only) report_only=1; shift ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "bench-shadows: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) scenarios+=("$1"); shift ;;
  esac
done

# Packages the benchmark needs beyond the build: the same check and install as install-deps.sh.
ensure_packages() {
  local missing=() p status
  for p in "$@"; do
    status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
    [[ "$status" == "install ok installed" ]] || missing+=("$p")
  done
  ((${#missing[@]} == 0)) && return 0
  command -v apt-get >/dev/null || return 1
  echo "bench-shadows: installing ${missing[*]}" >&2
  local sudo=()
  ((EUID == 0)) || sudo=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get update -qq >/dev/null &&
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends \
      "${missing[@]}" >/dev/null
}

if ((report_only)); then
  ensure_packages gnuplot-nox || echo "bench-shadows: gnuplot-nox not installed; no plot" >&2
  exec python3 "$root/scripts/bench_shadows.py" --report-only --out "$out"
fi

targets=(make_shadow_bench_scene)
[[ -n "$bin" ]] || targets+=(omnishadow)
if [[ -n "$build_dir" ]]; then
  build_dir=$(mkdir -p "$build_dir" && cd "$build_dir" && pwd)
  "$root/scripts/install-deps.sh"
  if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
    cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
  fi
  args=()
  for t in "${targets[@]}"; do args+=(--target "$t"); done
  if ! cmake --build "$build_dir" -j"$(nproc 2>/dev/null || echo 2)" "${args[@]}" \
      >"$build_dir/bench-build.log" 2>&1; then
    cat "$build_dir/bench-build.log" >&2
    exit 1
  fi
else
  "$root/scripts/build.sh" "${targets[@]}"
  build_dir="$root/build"
fi
[[ -n "$bin" ]] || bin="$build_dir/omnishadow"
[[ -x "$bin" ]] || { echo "bench-shadows: no executable $bin" >&2; exit 2; }
[[ -x /usr/bin/time ]] || ensure_packages time
ensure_packages gnuplot-nox || echo "bench-shadows: gnuplot-nox not installed; no plot" >&2

exec python3 "$root/scripts/bench_shadows.py" --bin "$bin" \
  --gen "$build_dir/make_shadow_bench_scene" --out "$out" --command "${command% }" \
  "${pass[@]}" "${scenarios[@]}"
