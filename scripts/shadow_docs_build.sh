# Sourced by make-shadow-gallery.sh and measure-shadow-quality.sh: build_targets T... builds
# the targets in $build_dir (a Release build, configured once) or, when $build_dir is empty,
# with scripts/build.sh into build/; it sets build_dir to an absolute path.
build_targets() {
  if [[ -z "$build_dir" ]]; then
    "$root/scripts/build.sh" "$@"
    build_dir="$root/build"
    return
  fi
  build_dir=$(mkdir -p "$build_dir" && cd "$build_dir" && pwd)
  "$root/scripts/install-deps.sh"
  if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
    cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
  fi
  local args=() t
  for t in "$@"; do args+=(--target "$t"); done
  if ! cmake --build "$build_dir" -j"$(nproc 2>/dev/null || echo 2)" "${args[@]}" \
      >"$build_dir/shadow-docs-build.log" 2>&1; then
    cat "$build_dir/shadow-docs-build.log" >&2
    exit 1
  fi
}
