#!/usr/bin/env bash
# One command for a newcomer: installs what is missing, builds, and renders the built-in demo
# scene to out/demo.png. Extra arguments go to `omnishadow render`.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" omnishadow
mkdir -p "$root/out"
"$root/build/omnishadow" render -o "$root/out/demo.png" "$@"
