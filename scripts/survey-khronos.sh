#!/usr/bin/env bash
# The "does every asset render?" survey: for every .gltf and .glb below the given folders, runs
# `omnishadow info` and a small `omnishadow render` and prints one Markdown table row per file:
# rendered (with the extension warnings it gave) or refused (with the message). Not a test:
# a table to read and to compare between two binaries.
# Usage: scripts/survey-khronos.sh [--binary PATH] [--size N] FOLDER...
#   e.g. scripts/survey-khronos.sh ../shared/scenes-khronos ../shared/scenes-thirdparty
#   --binary  the omnishadow to survey (default: build/omnishadow of this checkout)
#   --size    width and height of the renders (default 128; keep it small on shared machines)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
binary="$root/build/omnishadow"
size=128
folders=()
while [ $# -gt 0 ]; do
  case "$1" in
    --binary) binary=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) folders+=("$1"); shift ;;
  esac
done
if [ ${#folders[@]} -eq 0 ]; then
  echo "usage: $0 [--binary PATH] [--size N] FOLDER..." >&2
  exit 2
fi
[ -x "$binary" ] || { echo "$0: no executable $binary" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The error line of a failed run (the last "omnishadow: " line that is not a warning), or the
# warnings that name an extension, '; '-joined, with the scene's path taken out.
message() {
  local log=$1 file=$2 status=$3
  if [ "$status" -ne 0 ]; then
    { grep -v '^omnishadow: warning: ' "$log" || true; } | tail -n 1 |
      sed -e "s|^omnishadow: ||" -e "s|$file: ||"
  else
    { grep -E '^omnishadow: warning: .*(extension|KHR_|EXT_|MSFT_|not drawn)' "$log" || true; } |
      sed -e 's|^omnishadow: warning: ||' -e "s|$file: ||" | sort -u | paste -sd '\t' - |
      sed 's/\t/; /g'
  fi
}

echo "| file | info | render | message (refused) or extension warnings (rendered) |"
echo "|---|---|---|---|"
for folder in "${folders[@]}"; do
  mapfile -t files < <(find "$folder" -type f \( -name '*.gltf' -o -name '*.glb' \) | sort)
  for file in "${files[@]}"; do
    set +e
    "$binary" info "$file" </dev/null >/dev/null 2>"$work/info.log"
    info=$?
    timeout 300 "$binary" render "$file" --width "$size" --height "$size" \
      -o "$work/render.png" </dev/null >/dev/null 2>"$work/render.log"
    render=$?
    set -e
    infoText=$([ "$info" -eq 0 ] && echo ok || echo "exit $info")
    case "$render" in
      0) renderText=rendered ;;
      124) renderText="timed out" ;;
      *) renderText="refused (exit $render)" ;;
    esac
    text=$(message "$work/render.log" "$file" "$render")
    if [ "$render" -eq 0 ] && [ "$info" -ne 0 ]; then text="info: $(message "$work/info.log" "$file" "$info")"; fi
    echo "| $(basename "$folder")/${file#"$folder"/} | $infoText | $renderText | ${text//|/\\|} |"
    rm -f "$work/render.png"
  done
done
