#!/usr/bin/env bash
# Checks the Debian package scripts/package.sh built (or the .deb given): its files, and that
# every shared library the binary needs comes from a package it depends on. Then, with
# --install, installs it with `apt-get install ./omnishadow_*.deb`, renders the demo scene with
# /usr/bin/omnishadow (no arguments but the size: the scene comes from /usr/share/omnishadow),
# and removes the package again. --install needs root and changes the machine's packages, so it
# is no part of scripts/test.sh or CI: run it in a throwaway container or before a release.
# Usage: scripts/test-package.sh [--install] [package.deb]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
install=0
if [[ "${1:-}" == "--install" ]]; then install=1; shift; fi
deb=${1:-$(ls "$root"/build-package/omnishadow_*_amd64.deb)}
deb=$(realpath "$deb")
fail() { echo "test-package: $*" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dpkg-deb -c "$deb" | awk '{print $6}' >"$work/files"
for file in ./usr/bin/omnishadow ./usr/share/man/man1/omnishadow.1.gz \
            ./usr/share/doc/omnishadow/README.md ./usr/share/omnishadow/demo/room.gltf \
            ./usr/share/omnishadow/demo/room.lights.json; do
  grep -qx "$file" "$work/files" || fail "$deb has no $file"
done
depends=$(dpkg-deb -f "$deb" Depends)
# The package names alone, one a line.
dpkg-deb -f "$deb" Depends | tr ',|' '\n\n' | awk '{print $1}' >"$work/depends"
# Every library the binary itself needs, found on this machine, belongs to a package in Depends.
dpkg-deb -x "$deb" "$work/root"
binary="$work/root/usr/bin/omnishadow"
for needed in $(objdump -p "$binary" | awk '/NEEDED/ {print $2}'); do
  path=$(ldd "$binary" | awk -v lib="$needed" '$1 == lib {print $3}')
  [[ -n "$path" ]] || fail "$needed: not found on this machine"
  package=$(dpkg -S "$(realpath "$path")" 2>/dev/null | head -1 | cut -d: -f1) ||
    package=$(dpkg -S "$path" | head -1 | cut -d: -f1)
  grep -qxF "$package" "$work/depends" || fail "$needed ($package) is not in Depends: $depends"
done
zcat "$work/root/usr/share/man/man1/omnishadow.1.gz" | grep -q -- '--job-timeout' ||
  fail "the man page lacks batch's options"
echo "test-package: $(basename "$deb"): files and Depends ($depends) ok"
((install)) || exit 0

((EUID == 0)) || fail "--install needs root"
if dpkg -s omnishadow >/dev/null 2>&1; then fail "omnishadow is installed already; not touching it"; fi
trap 'apt-get remove -y -qq omnishadow >/dev/null 2>&1 || true; rm -rf "$work"' EXIT
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$deb" >/dev/null
mkdir "$work/render"
(cd "$work/render" && /usr/bin/omnishadow render --width 160 --height 120 -o demo.png)
[[ "$(head -c 8 "$work/render/demo.png" | od -An -tx1 | tr -d ' \n')" == 89504e470d0a1a0a ]] ||
  fail "/usr/bin/omnishadow render wrote no PNG"
/usr/bin/omnishadow devices >/dev/null
echo "test-package: apt-get installed it, /usr/bin/omnishadow rendered the demo; removing it"
