#!/usr/bin/env bash
# The frame-speed tables on a machine with a GPU (issue 19): the peers' scenes (process, cold and
# warm first frame, steady frame, the image against llvmpipe's), the shadow passes on the bench
# room, 256 shadowed point lights on 1M triangles, batch scenes per second. Runs
# scripts/bench_gpu.py; on a machine without a GPU the same tables measure llvmpipe.
#
# Usage: scripts/bench-gpu.sh [--out DIR] [--rounds N] [--repeat N] [--sections LIST]
#        scripts/bench-gpu.sh --bundle DIR [--baseline BIN]
# --bundle DIR  build here and pack into DIR what a machine that cannot build needs: the
#               binaries, the shared libraries they load beyond glibc, the scenes with the
#               peers' lights, llvmpipe's images of them, and DIR/run.sh. There:
#               `DIR/run.sh OUT [bench_gpu.py options]` (gives the binaries the bundled
#               libraries, and NVIDIA's EGL vendor file when it exists; stops with status 3
#               when EGL lists no hardware device, unless ALLOW_SOFTWARE=1).
# --baseline BIN  (with --bundle) another omnishadow, packed as bin/omnishadow.baseline and timed
#               in the same rounds as this build's (the peers' steady frames, the many-lights
#               frame): one lease measures a change against what came before.
# --out DIR     where gpu.md and the images go (default build-bench/gpu)
# The scenes come from ../shared (peers/threejs/scenes and scenes-thirdparty).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
shared="$root/../shared"
bundle="" baseline="" out="$root/build-bench/gpu" passthrough=()
while (($#)); do
  case $1 in
    --bundle) bundle=$2; shift 2 ;;
    --baseline) baseline=$(realpath "$2"); shift 2 ;;
    --out) out=$2; shift 2 ;;
    --rounds|--repeat|--sections|--batch-scenes|--many-triangles|--many-resolutions|--many-passes) passthrough+=("$1" "$2"); shift 2 ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "bench-gpu: unknown argument $1" >&2; exit 2 ;;
  esac
done
"$root/scripts/build.sh" omnishadow make_shadow_bench_scene make_bench_scenes

# The peers' scenes with compare.py's lights (its SCENES and with_filter: pcf, 1024^2, a range
# of 0 means none), as NAME.glb or NAME.gltf beside NAME.lights.json.
make_scenes() {
  python3 - "$1" "$shared/peers" "$root/scripts" <<'PY'
import os, shutil, sys, tempfile
dir, peers, scripts = sys.argv[1:4]
sys.path.insert(0, scripts)
from bench_peers import load_compare
cmp = load_compare(peers)
os.makedirs(dir, exist_ok=True)
tmp = tempfile.mkdtemp()
for name in ("box", "cornell", "sundial", "whackamole", "test_room"):
    scene, lights = cmp["SCENES"][name]
    stem, ext = os.path.splitext(os.path.basename(scene))
    shutil.copy(scene, os.path.join(dir, name + ext))
    if ext == ".gltf":  # its buffers, under the names its URIs give them
        folder = os.path.dirname(scene)
        for f in os.listdir(folder):
            if f.startswith(stem) and f.endswith(".bin"):
                shutil.copy(os.path.join(folder, f), dir)
    shutil.copy(cmp["with_filter"](lights, "pcf", tmp), os.path.join(dir, name + ".lights.json"))
shutil.rmtree(tmp)
PY
}

# This machine's images of the same renders (llvmpipe here), for `omnishadow diff` against the GPU's.
make_references() {
  local scenes=$1 dir=$2
  mkdir -p "$dir"
  for n in box cornell sundial whackamole test_room; do
    local scene=("$scenes/$n".gl*)
    "$root/build/omnishadow" render "${scene[0]}" \
      -l "$scenes/$n.lights.json" -o "$dir/$n.png" --width 1280 --height 720 --no-gltf-lights \
      >/dev/null
  done
  # The occlusion estimate alone, for bench_gpu.py's occlusion section.
  for n in cornell sundial whackamole test_room; do
    local scene=("$scenes/$n".gl*) lights
    lights=$(python3 -c 'import sys; sys.path.insert(0, sys.argv[1])
from bench_gpu import occlusion_lights
print(occlusion_lights(*sys.argv[2:5], True))' "$root/scripts" "$scenes/$n.lights.json" "$dir" "$n")
    "$root/build/omnishadow" render "${scene[0]}" -l "$lights" -o "$dir/$n.occlusion.png" \
      --width 1280 --height 720 --no-gltf-lights --debug-view occlusion >/dev/null
    rm "$lights"
  done
}

if [[ -n "$bundle" ]]; then
  rm -rf "$bundle"
  mkdir -p "$bundle/bin" "$bundle/lib"
  for b in omnishadow make_shadow_bench_scene make_bench_scenes; do
    strip -o "$bundle/bin/$b" "$root/build/$b"
  done
  [[ -n "$baseline" ]] && strip -o "$bundle/bin/omnishadow.baseline" "$baseline"
  # Every library beyond glibc: the other machine may have none of Debian's packages, and
  # glvnd's loaders (libEGL, libOpenGL) find the vendor's driver there.
  ldd "$root"/build/{omnishadow,make_shadow_bench_scene,make_bench_scenes} ${baseline:+"$baseline"} |
    awk '/=>/ { print $3 }' | sort -u |
    grep -vE '/(libc|libm|libpthread|libdl|librt|ld-linux[^/]*)\.so' |
    while read -r lib; do cp -L "$lib" "$bundle/lib/"; done
  cp "$root/scripts/bench_gpu.py" "$bundle/"
  make_scenes "$bundle/scenes"
  make_references "$bundle/scenes" "$bundle/reference"
  cat >"$bundle/run.sh" <<'SH'
#!/usr/bin/env bash
# Runs bench_gpu.py from this bundle: run.sh OUT [bench_gpu.py options]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$1; shift
# The bundled libraries go to the binaries alone (bench_gpu.py's --ld-library-path): that
# machine's Python needs its own versions of libraries the bundle carries too.
libs="$here/lib"
for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do
  [[ -d $d ]] && libs="$libs:$d"
done
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[[ -f $vendor && -z ${__EGL_VENDOR_LIBRARY_FILENAMES:-} ]] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
# A GPU's tables from llvmpipe would mislead: stop unless EGL lists a hardware device (or
# ALLOW_SOFTWARE=1, to try the bundle on a machine without one).
if ! LD_LIBRARY_PATH="$libs" "$here/bin/omnishadow" devices | grep -q ' hardware$' &&
  [[ -z ${ALLOW_SOFTWARE:-} ]]; then
  echo "run.sh: EGL lists no hardware device:" >&2
  LD_LIBRARY_PATH="$libs" "$here/bin/omnishadow" devices >&2 || true
  env | grep -E '^(__EGL|__GL|LD_LIBRARY_PATH|CUDA_VISIBLE)' >&2 || true
  exit 3
fi
baseline=()
[[ -x $here/bin/omnishadow.baseline ]] && baseline=(--baseline-bin "$here/bin/omnishadow.baseline")
exec python3 "$here/bench_gpu.py" --bin "$here/bin/omnishadow" "${baseline[@]}" --ld-library-path "$libs" \
  --shadow-gen "$here/bin/make_shadow_bench_scene" --batch-gen "$here/bin/make_bench_scenes" \
  --scenes "$here/scenes" --reference "$here/reference" --out "$out" "$@"
SH
  chmod +x "$bundle/run.sh"
  du -sh "$bundle"
  exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
make_scenes "$work/scenes"
python3 "$root/scripts/bench_gpu.py" --bin "$root/build/omnishadow" \
  --shadow-gen "$root/build/make_shadow_bench_scene" --batch-gen "$root/build/make_bench_scenes" \
  --scenes "$work/scenes" --out "$out" "${passthrough[@]}"
