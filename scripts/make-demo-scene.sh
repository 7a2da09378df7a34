#!/usr/bin/env bash
# Regenerates scenes/demo/room.gltf from scenes/builder/make_demo_scene.cpp.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" make_demo_scene
"$root/build/make_demo_scene" "$root/scenes/demo/room.gltf"
echo "wrote scenes/demo/room.gltf"
