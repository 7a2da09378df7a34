#!/usr/bin/env bash
# Installs the Debian 12 packages omnishadow needs to build, render and test.
# Idempotent and quiet: when everything is present it prints nothing and touches nothing.
set -euo pipefail

packages=(
  # toolchain (lld: the linker, CMakeLists.txt)
  cmake g++ make pkg-config lld
  # headless OpenGL through glvnd + Mesa (llvmpipe when there is no GPU)
  libegl-dev libopengl-dev libgl-dev libegl1 libopengl0 libegl-mesa0 libgl1-mesa-dri
  # libraries
  libtinygltf-dev libglm-dev libopenimageio-dev libopenexr-dev libcli11-dev nlohmann-json3-dev
  libgtest-dev
  # PNG and EXR without OpenImageIO on the start-up path (OpenImageIO is a plugin for the rest)
  libpng-dev libdeflate-dev
  # JPEG, WebP and AVIF textures
  libturbojpeg0-dev libwebp-dev libavif-dev
  # digests of the textures kept between renders (the header, compiled in)
  libxxhash-dev
  # compressed glTF geometry (KHR_draco_mesh_compression, EXT/KHR_meshopt_compression)
  libdraco-dev libmeshoptimizer-dev
  # exact shadow rays for `omnishadow verify`
  libembree-dev
  # the Python module (python/) and its tests: Debian's python3 with NumPy and pytest
  pybind11-dev python3-dev python3-numpy python3-pytest
  # fuzzing (scripts/fuzz.sh): clang with libFuzzer and the sanitizer runtimes
  clang libclang-rt-14-dev
  # OpenImageIO's CMake config refers to its command-line tools (and they are handy: idiff, iinfo)
  openimageio-tools
  # the Debian package (scripts/package.sh): the man page from --help
  help2man
  # the clean root scripts/test-package.sh --chroot installs the package into
  debootstrap
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
((${#missing[@]} == 0)) && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo=()
((EUID == 0)) || sudo=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq >/dev/null
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
