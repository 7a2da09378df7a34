#!/usr/bin/env bash
# Runs the whole glTF-Validator test suite through `omnishadow info` and `omnishadow render`
# (32x32, a timeout per run) and reports exit codes against each file's expected report:
# signals, hangs, malformed errors, and exit 0 on files with validation errors (with or without
# a warning). Exit status 1 when a crash, hang or malformed error was found.
#   scripts/validator-suite.sh [SUITE] [--timeout S] [--jobs N] [--json FILE]
# SUITE defaults to ../shared/gltf-validator-tests (the lead's test data); the binary is
# build/omnishadow, built by scripts/build.sh when missing (OMNISHADOW_BINARY overrides it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
suite="$root/../shared/gltf-validator-tests"
if [[ $# -gt 0 && "$1" != --* ]]; then
  suite=$1
  shift
fi
[[ -d "$suite" ]] || { echo "validator-suite.sh: no suite at $suite" >&2; exit 2; }
binary=${OMNISHADOW_BINARY:-$root/build/omnishadow}
if [[ ! -x "$binary" ]]; then
  "$root/scripts/build.sh" omnishadow
fi
exec python3 "$root/scripts/validator_suite.py" "$binary" "$suite" "$@"
