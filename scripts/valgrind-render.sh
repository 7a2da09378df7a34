#!/usr/bin/env bash
# valgrind memcheck of one small render of the demo scene with the normal (RelWithDebInfo)
# build: exits 0 only when memcheck reports no error and no leak beyond the known platform ones
# in tests/sanitizers/valgrind.supp. Extra arguments go to `omnishadow render`.
# Takes a few minutes: llvmpipe's JIT-compiled shaders run under valgrind's emulation.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" omnishadow

if ! command -v valgrind >/dev/null; then
  echo "valgrind-render: installing valgrind" >&2
  sudo=()
  ((EUID == 0)) || sudo=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq >/dev/null
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends valgrind >/dev/null
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The demo's two shadowed point lights, with 64x64 shadow cube maps instead of 1024x1024.
cat >"$tmp/lights.json" <<'JSON'
{
  "ambient": [0.02, 0.02, 0.02],
  "lights": [
    {"name": "warm", "type": "point", "position": [-0.8, 3.0, 0.6], "color": [1.0, 0.85, 0.65],
     "intensity": 14, "shadow": {"resolution": 64, "near": 0.08, "filter": "pcf-disk"}},
    {"name": "cool", "type": "point", "position": [2.4, 2.2, 1.0], "color": [0.7, 0.8, 1.0],
     "intensity": 8, "shadow": {"resolution": 64, "near": 0.08, "filter": "pcf"}}
  ]
}
JSON

log="$tmp/valgrind.log"
start=$SECONDS
status=0
valgrind --tool=memcheck --leak-check=full --error-exitcode=1 --keep-debuginfo=yes \
  --num-callers=40 --suppressions="$root/tests/sanitizers/valgrind.supp" --log-file="$log" \
  "$root/build/omnishadow" render "$root/scenes/demo/room.gltf" -l "$tmp/lights.json" \
  --width 64 --height 48 -o "$tmp/render.png" "$@" || status=$?
elapsed=$((SECONDS - start))

if ((status != 0)) || [[ ! -s "$tmp/render.png" ]]; then
  cat "$log" >&2
  echo "valgrind-render: FAILED (exit status $status, ${elapsed}s)" >&2
  exit 1
fi
# The verdict, in memcheck's words: errors, and the leak summary.
grep -E 'ERROR SUMMARY|definitely lost|indirectly lost|possibly lost|suppressed:' "$log" |
  sed -E 's/^==[0-9]+== +//'
echo "valgrind-render: clean (${elapsed}s)"
