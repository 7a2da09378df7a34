#!/usr/bin/env bash
# Seeds the fuzzers' working corpora: DEST/corpus-lights/, DEST/corpus-gltf/,
# DEST/corpus-manifest/ and DEST/corpus-hdr/ (DEST defaults
# to build-fuzz/). Existing files are kept, so a corpus grown by earlier runs keeps growing.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
dest=${1:-"$root/build-fuzz"}
mkdir -p "$dest/corpus-lights" "$dest/corpus-gltf" "$dest/corpus-manifest" "$dest/corpus-hdr"

seed() {  # seed CORPUS FILE...: copies each file in as seed-<name>, unless already there
  local corpus=$1
  shift
  for file in "$@"; do
    cp -n "$file" "$dest/corpus-$corpus/seed-$(basename "$file")"
  done
}

seed lights "$root"/scenes/demo/*.json "$root"/tests/fuzz/corpus-lights/*.json
seed hdr "$root"/tests/fuzz/corpus-hdr/*.hdr
# .gltf files with external .bin files do not resolve from the fuzzer's temp folder; they still
# exercise the JSON side.
# Compressed geometry reaches the Draco and meshopt decoders: corpus-gltf/draco-box.gltf is
# scenes/compressed/Box-Draco with its .bin embedded; meshopt.glb is self-contained.
seed gltf "$root"/tests/fuzz/corpus-gltf/*.gltf \
  "$root/scenes/thirdparty/Box/Box.glb" \
  "$root/scenes/thirdparty/BoxTextured/BoxTextured.glb" \
  "$root/scenes/thirdparty/Duck/Duck.glb" \
  "$root/scenes/thirdparty/CornellBoxSuzanne/cornell-box.glb" \
  "$root/scenes/thirdparty/Cameras/Cameras.gltf" \
  "$root/scenes/demo/room.gltf" \
  "$root/scenes/compressed/CornellBoxSuzanne/meshopt.glb" \
  "$root/scenes/compressed/CornellBoxSuzanne/quantized.glb" \
  "$root/scenes/compressed/SimpleInstancing/SimpleInstancing.glb"
seed manifest "$root"/tests/fuzz/corpus-manifest/*.json

# Deep nesting, generated: just inside the JSON depth limit (128) and far past it, where
# tinygltf's and nlohmann's recursion once overflowed the stack.
nested() {  # nested DEPTH: DEPTH '[' then DEPTH ']'
  printf '%*s' "$1" '' | tr ' ' '['
  printf '%*s' "$1" '' | tr ' ' ']'
}
deep() {  # deep CORPUS NAME PREFIX SUFFIX: seeds at depths 120 and 100000
  local depth
  for depth in 120 100000; do
    [[ -e "$dest/corpus-$1/seed-deep-$depth-$2" ]] && continue
    { printf '%s' "$3"; nested "$depth"; printf '%s' "$4"; } >"$dest/corpus-$1/seed-deep-$depth-$2"
  done
}
deep lights lights.json '{"lights": ' '}'
deep lights ambient.json '{"ambient": ' ', "lights": []}'
deep manifest manifest.json '{"jobs": [{"scene": "a.gltf", "outputs": ["a.png"], "extras": ' '}]}'
deep gltf extras.gltf '{"asset": {"version": "2.0"}, "extras": ' '}'
deep gltf node.gltf '{"asset": {"version": "2.0"}, "nodes": [{"extras": ' '}], "scenes": [{"nodes": [0]}]}'
# The same JSON as a .glb: 12-byte header, then the JSON chunk (padded to 4 bytes).
glb_from_json='
import struct, sys
text = sys.stdin.buffer.read()
text += b" " * (-len(text) % 4)
with open(sys.argv[1], "wb") as f:
    f.write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(text)))
    f.write(struct.pack("<I", len(text)) + b"JSON" + text)
'
for depth in 120 100000; do
  glb="$dest/corpus-gltf/seed-deep-$depth-extras.glb"
  [[ -e "$glb" ]] && continue
  { printf '{"asset": {"version": "2.0"}, "extras": '; nested "$depth"; printf '}'; } |
    python3 -c "$glb_from_json" "$glb"
done
