#!/usr/bin/env bash
# Builds the Debian package omnishadow_<version>_amd64.deb with CPack into build-package/: the
# binary (built to find the demo scene where the package installs it), a man page generated from
# --help with help2man, the README, the licenses and the demo scene; its dependencies come from
# the binary's shared libraries (dpkg-shlibdeps). Prints the package's path.
# scripts/test-package.sh installs it and renders the demo from /usr/bin.
# Usage: scripts/package.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
build="$root/build-package"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_INSTALL_PREFIX=/usr \
  -DOMNISHADOW_BUILD_TESTS=OFF -DOMNISHADOW_PYTHON=OFF -DOMNISHADOW_PLUGIN_BUILD_DIR=OFF \
  -DOMNISHADOW_DEMO_SCENE=/usr/share/omnishadow/demo/room.gltf \
  "${launcher[@]}" >/dev/null
cmake --build "$build" -j"$(nproc 2>/dev/null || echo 2)" --target omnishadow >"$build/build.log" 2>&1 ||
  { cat "$build/build.log" >&2; exit 1; }

# The man page: every command's --help, one section each.
man="$build/omnishadow.1"
cat >"$build/commands.h2m" <<'H2M'
[DESCRIPTION]
omnishadow renders glTF 2.0 scenes headlessly through EGL and OpenGL 4.5, with omnidirectional
point-light shadows. Commands: render, info, batch, diff, verify, devices, report merge; each
has its own options, listed below. The README in /usr/share/doc/omnishadow has the details.
H2M
for command in render info batch diff verify devices "report merge"; do
  {
    echo "[COMMAND: omnishadow $command]"
    # shellcheck disable=SC2086 # "report merge" is two words on purpose
    "$build/omnishadow" $command --help | sed 's/^/ /'
  } >>"$build/commands.h2m"
done
help2man --no-info --no-discard-stderr --include "$build/commands.h2m" \
  --name "headless glTF renderer with omnidirectional point-light shadows" \
  --version-string "$("$build/omnishadow" --version | awk '{print $2}')" \
  -o "$man" "$build/omnishadow"
gzip -9nf "$man"
cmake -S "$root" -B "$build" -DOMNISHADOW_MAN_PAGE="$man.gz" >/dev/null

(cd "$build" && cpack -G DEB >"$build/cpack.log" 2>&1) || { cat "$build/cpack.log" >&2; exit 1; }
ls "$build"/omnishadow_*_amd64.deb
