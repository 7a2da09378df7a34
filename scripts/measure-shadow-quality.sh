#!/usr/bin/env bash
# Measures shadow quality against the exact reference (`omnishadow verify`) and the cost of each
# shadow filter, and writes docs/shadow-quality.md (also printed to stdout).
#
# Usage: scripts/measure-shadow-quality.sh [--build-dir DIR] [--work DIR] [--doc FILE]
#            [--runs N]
#
#  - The demo scene (scenes/demo/room.gltf) at 640x360, one light per render (point, spot,
#    directional with 2 cascades; the lights of scripts/make-shadow-gallery.sh), each filter:
#    `omnishadow verify --json` per light type x filter (interior and edge agreement, false
#    shadow, false light, evaluated and skipped points), and the median of the "shadow maps"
#    and "lighting" stages of `omnishadow render --stats` over N runs (default 3), the runs
#    interleaved over all configurations.
#  - Two focused scenes from make_shadow_quality_scenes: a plane lit at a grazing 80 degrees by
#    a point, a spot and a directional light (acne), and a 2 cm board standing on a floor
#    (leaks at the contact), verified per filter.
# Default bias settings everywhere. Rows missing issue 3's bar (interior agreement >= 99.9%,
# false shadow and false light <= 0.05%) are marked **MISS**.
#
# --build-dir DIR  build a Release omnishadow and the scene generator in DIR (default:
#                  scripts/build.sh, into build/).
# --work DIR       lights files, scenes, error images (<scene>-<type>-<filter>-errors.png) and
#                  results.json (default: <build dir>/shadow-quality).
# --doc FILE       the markdown report (default docs/shadow-quality.md; "-" = stdout only).
# Takes about 5 minutes on 2 cores with llvmpipe.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
printf -v command '%q ' scripts/measure-shadow-quality.sh "$@"
build_dir=""
work=""
doc="$root/docs/shadow-quality.md"
pass=()
while (($#)); do
  case "$1" in
    --build-dir) build_dir=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --doc) doc=$2; shift 2 ;;
    --runs) pass+=(--runs "$2"); shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "measure-shadow-quality: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
source "$root/scripts/shadow_docs_build.sh"
build_targets omnishadow make_shadow_quality_scenes
[[ -n "$work" ]] || work="$build_dir/shadow-quality"
[[ "$doc" == "-" ]] && doc_args=() || doc_args=(--doc "$doc")
exec python3 "$root/scripts/shadow_docs.py" measure --bin "$build_dir/omnishadow" \
  --gen "$build_dir/make_shadow_quality_scenes" --work "$work" "${doc_args[@]}" \
  --command "${command% }" "${pass[@]}"
