#!/usr/bin/env bash
# Renders a fixed set of jobs with two omnishadow binaries and checks that every output file is
# byte-identical: the check behind refactorings that must not change behaviour.
#
# Usage: scripts/compare-outputs.sh OLD_BINARY NEW_BINARY [WORK_DIR]
#
# The jobs: the demo (PNG, EXR, AOVs with every layer, shadow map dumps, light views, each debug
# view, phong shading, each --shadow-pass, mixed lights with every layer and masks), the scenes
# in scenes/thirdparty with the demo's lights (with every AOV layer and masks) and with a point
# light (alone and with masks), a point, a spot and a directional light with every filter on
# the demo room, a batch of several cameras (shadow cache), and `info --json` of every scene.
# Prints one line per differing file and exits 1 when any differs; 0 when all are identical.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
old=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d)}
mkdir -p "$work"
demo="$root/scenes/demo/room.gltf"

# Lights files: one per light type and filter.
lights="$work/lights"
mkdir -p "$lights"
for filter in hard pcf pcf-disk poisson pcss vsm; do
  cat >"$lights/point-$filter.json" <<JSON
{"ambient": [0.02, 0.02, 0.02], "lights": [{"name": "warm", "type": "point",
 "position": [-0.8, 3.0, 0.6], "intensity": 14,
 "shadow": {"near": 0.08, "filter": "$filter", "lightRadius": 0.15}}]}
JSON
  cat >"$lights/spot-$filter.json" <<JSON
{"lights": [{"name": "spot", "type": "spot", "position": [2.6, 3.6, 1.4],
 "direction": [-2.8, -3.6, -1.9], "innerConeAngle": 0.55, "outerConeAngle": 0.7,
 "intensity": 40, "shadow": {"near": 0.08, "filter": "$filter", "lightRadius": 0.15}}]}
JSON
  cat >"$lights/sun-$filter.json" <<JSON
{"lights": [{"name": "sun", "type": "directional", "direction": [-0.5, -0.45, -1.0],
 "intensity": 5, "shadow": {"cascades": 2, "filter": "$filter", "lightRadius": 0.02}}]}
JSON
done
cat >"$lights/mixed.json" <<JSON
{"lights": [
 {"name": "warm", "type": "point", "position": [-0.8, 3.0, 0.6], "intensity": 14},
 {"name": "ranged", "type": "point", "position": [1.5, 1.0, 2.0], "intensity": 6, "range": 3},
 {"name": "spot", "type": "spot", "position": [2.6, 3.6, 1.4], "direction": [-2.8, -3.6, -1.9],
  "outerConeAngle": 0.7, "intensity": 40, "shadow": {"filter": "vsm"}},
 {"name": "sun", "type": "directional", "direction": [-0.5, -0.45, -1.0], "intensity": 2},
 {"name": "fill", "type": "point", "position": [0, 3.5, 4], "intensity": 3, "shadow": {"enabled": false}}]}
JSON
cat >"$work/batch.json" <<JSON
{"jobs": [
 {"scene": "$demo", "outputs": ["a.png"], "eye": [0, 2, 8]},
 {"scene": "$demo", "outputs": ["b.png", "b.exr"], "eye": [2, 2.5, 7], "target": [0, 1, 0]},
 {"scene": "$demo", "lights": "$lights/mixed.json", "outputs": ["c.png"]}]}
JSON

# Each job: a name, then the arguments; "@OUT" is the output folder (the working folder of the job).
jobs=(
  "demo|render $demo -o @OUT/demo.png -o @OUT/demo.exr --aov @OUT/aovs.exr --aov-layers all --width 320 --height 180"
  "demo-dumps|render $demo -o @OUT/demo.png --dump-depth @OUT/depth --light-views @OUT/views --light-view-size 64 --width 160 --height 90"
  "demo-phong|render $demo --shading phong -o @OUT/phong.png --width 320 --height 180"
  "demo-exposure|render $demo --exposure 1.5 -o @OUT/bright.png --width 320 --height 180"
  "demo-mixed|render $demo -l $lights/mixed.json -o @OUT/mixed.png --aov @OUT/mixed.exr --aov-layers all --masks @OUT/mixed --width 320 --height 180"
)
for view in shadow depth normals albedo lightcount; do
  jobs+=("debug-$view|render $demo --debug-view $view -o @OUT/$view.png --width 160 --height 90")
done
for pass in six geometry instanced; do
  jobs+=("pass-$pass|render $demo --shadow-pass $pass -o @OUT/$pass.png --width 160 --height 90")
done
for type in point spot sun; do
  for filter in hard pcf pcf-disk poisson pcss vsm; do
    jobs+=("$type-$filter|render $demo -l $lights/$type-$filter.json -o @OUT/$type-$filter.png --aov @OUT/$type-$filter.exr --width 240 --height 135")
  done
done
for scene in "$root"/scenes/thirdparty/*/*.gl*; do
  name=$(basename "${scene%.*}")
  jobs+=("scene-$name|render $scene -o @OUT/$name.png --aov @OUT/$name.exr --aov-layers all --masks @OUT/$name --width 240 --height 135")
  jobs+=("lit-$name|render $scene -l $lights/point-pcf.json -o @OUT/lit-$name.png --width 240 --height 135")
  jobs+=("masks-$name|render $scene -l $lights/point-pcf.json -o @OUT/m-$name.png --masks @OUT/m-$name --width 240 --height 135")
  jobs+=("info-$name|info --json $scene")
done
jobs+=("batch|batch $work/batch.json --out @OUT --width 160 --height 90")

run_all() {
  local binary=$1 side=$2
  for entry in "${jobs[@]}"; do
    local name=${entry%%|*} args=${entry#*|}
    local out="$work/$side/$name"
    rm -rf "$out"
    mkdir -p "$out"
    # shellcheck disable=SC2086
    (cd "$out" && "$binary" ${args//@OUT/.} >"$out/stdout.txt" 2>"$out/stderr.txt"; echo "exit $?" >"$out/status.txt")
    # Times and the binary's own path differ between runs: keep only what must be identical.
    sed -i -E '/^ *(load|context|shaders|upload|shadow maps|lighting|readback|encode|layers|light views|total) /d' "$out/stderr.txt"
    sed -i -E 's/ \([0-9.]+ ms\)//; s/ in [0-9.]+ s$//' "$out/stdout.txt"
  done
}
run_all "$old" old
run_all "$new" new

differ=0
while IFS= read -r file; do
  if [[ ! -f "$work/new/$file" ]]; then
    echo "missing in new: $file"
    differ=1
  elif ! cmp -s "$work/old/$file" "$work/new/$file"; then
    echo "differs: $file"
    differ=1
  fi
done < <(cd "$work/old" && find . -type f | sort)
while IFS= read -r file; do
  [[ -f "$work/old/$file" ]] || { echo "only in new: $file"; differ=1; }
done < <(cd "$work/new" && find . -type f | sort)
count=$(cd "$work/old" && find . -type f | wc -l)
if ((differ)); then
  echo "compare-outputs: files differ (outputs in $work)"
  exit 1
fi
echo "compare-outputs: all $count files byte-identical (${#jobs[@]} jobs, outputs in $work)"
