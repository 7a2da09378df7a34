#!/usr/bin/env bash
# Renders the shadow filter gallery of the README's "Shadow settings" section: the demo scene
# (scenes/demo/room.gltf) once per filter (hard, pcf, pcf-disk, poisson, pcss, vsm) for each
# light type, with lights files it writes itself (scripts/shadow_docs.py: the demo's warm point
# light; a spot light aimed at the floor objects; a sun at a slant with 2 cascades; pcss with a
# light radius of 0.15 m, or 0.02 rad for the sun; every other shadow setting at its default).
#
# Usage: scripts/make-shadow-gallery.sh [--build-dir DIR] [--out DIR] [--width W --height H]
#
# --out DIR        where <type>-<filter>.png and the contact sheets <type>-filters.png go
#                  (default docs/images/shadows). Type: point, spot, directional.
# --build-dir DIR  build a Release omnishadow in DIR (default: scripts/build.sh, into build/).
# --width, --height  picture size (default 480x270).
#
# Deterministic: rerunning it rewrites the same pictures (the renderer's PNGs are byte-identical
# for the same inputs). Contact sheets need oiiotool (openimageio-tools); labels need the
# DejaVu font (fonts-dejavu-core), else the sheets have none.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out="$root/docs/images/shadows"
build_dir=""
size=()
while (($#)); do
  case "$1" in
    --out) out=$2; shift 2 ;;
    --build-dir) build_dir=$2; shift 2 ;;
    --width|--height) size+=("$1" "$2"); shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "make-shadow-gallery: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
source "$root/scripts/shadow_docs_build.sh"
build_targets omnishadow
exec python3 "$root/scripts/shadow_docs.py" gallery --bin "$build_dir/omnishadow" --out "$out" \
  "${size[@]}"
