# Sourced by the batch benchmarks: builds omnishadow and the scene generator, and generates
# COUNT small scenes with SEED into "$work/scenes" (a temporary folder removed on exit).
# Sets root, work and bin.
# Usage: make_bench_scenes COUNT SEED
make_bench_scenes() {
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
  "$root/scripts/build.sh" omnishadow make_bench_scenes
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  "$root/build/make_bench_scenes" "$work/scenes" "$1" "$2"
  bin="$root/build/omnishadow"
}
