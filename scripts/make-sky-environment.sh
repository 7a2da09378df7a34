#!/usr/bin/env bash
# Regenerates scenes/environments/sky.exr from scenes/builder/make_sky_environment.cpp.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" make_sky_environment
mkdir -p "$root/scenes/environments"
"$root/build/make_sky_environment" "$root/scenes/environments/sky.exr"
echo "wrote scenes/environments/sky.exr"
