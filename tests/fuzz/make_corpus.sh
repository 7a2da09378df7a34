#!/usr/bin/env bash
# Seeds the fuzzers' working corpora: DEST/corpus-lights/ and DEST/corpus-gltf/ (DEST defaults
# to build-fuzz/). Existing files are kept, so a corpus grown by earlier runs keeps growing.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
dest=${1:-"$root/build-fuzz"}
mkdir -p "$dest/corpus-lights" "$dest/corpus-gltf"

seed() {  # seed CORPUS FILE...: copies each file in as seed-<name>, unless already there
  local corpus=$1
  shift
  for file in "$@"; do
    cp -n "$file" "$dest/corpus-$corpus/seed-$(basename "$file")"
  done
}

seed lights "$root"/scenes/demo/*.json "$root"/tests/fuzz/corpus-lights/*.json
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
