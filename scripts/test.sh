#!/usr/bin/env bash
# One command for the whole test suite: installs what is missing, builds everything, runs CTest.
# Rendering tests use whatever EGL offers; on machines without a GPU that is Mesa's llvmpipe.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
jobs=$(nproc 2>/dev/null || echo 2)
cd "$root/build"
ctest --output-on-failure -j"$jobs" "$@"
