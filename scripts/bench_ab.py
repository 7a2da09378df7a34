#!/usr/bin/env python3
"""Two omnishadow binaries side by side, stage by stage, without three.js (issue 19).

The A/B measurement behind the before/after numbers of docs/performance.md: on the scenes and
lights of ../shared/peers/compare.py (the same ones scripts/bench-peers.sh times), each round
runs, for each scene and each binary, a single `render` (its first frame) and a `render --repeat
N` (its steady frames), the binaries taking turns at going first. No Chromium runs between the
processes, so small differences (a millisecond of `lighting`) stand out of the noise that
bench-peers.sh's rounds carry. Prints a markdown table of medians, per scene and binary: steady
shadow maps, lighting, readback, layers and frame; first-frame shadow maps, lighting and frame
(shadow maps + lighting + readback + layer passes); the single render's `total` (all its
stages, the context and the load included: work moved out of the first frame into another stage
shows there, not in the first frame); process wall time.

--idle S sleeps S seconds before each process: what a single render meets after a pause rather
than right after another render. On a virtual machine whose host takes back the memory a guest
frees (virtio-balloon's free page reporting, as here), memory the last process handed back is
then gone from the host, and faulting it in again costs more (docs/performance.md, "Huge pages
only while they fault quickly"). --no-steady leaves out the `--repeat` processes.

--outputs "ARGS" adds render arguments to every process, for outputs beyond the PNG, with {tmp}
standing for a scratch folder: --outputs "--masks {tmp}/m" or --outputs "--aov {tmp}/a.exr
--aov-layers all". The frames then count their layer passes (steady frame and first frame alike).

--cold adds, for each scene and binary, a single render with an empty shader cache (a new
MESA_SHADER_CACHE_DIR each time), as on a fresh machine or in a container: the table gains its
first frame, `shaders` stage and process time. The other processes use the shader cache as it
is (warm after the first round).

--hog MB runs, before each single render, a process that fills MB megabytes and exits, then
waits --hog-wait S seconds (default 0.5): what a render meets right after a large process such
as Chromium (scripts/bench-peers.sh runs one between renders). The host takes back the memory
the hog freed, and fresh pages fault slowly for a while (docs/performance.md, "The slow mode
after Chromium, reproduced without it"); every binary meets that in every round, instead of
whichever runs right after three.js in bench-peers.sh.

--user UID runs every process as that user (`setpriv`; needs root), as in a container run as a
user of its own (`docker run --user UID`): for a UID without an entry in the password database
Mesa finds no home for its shader cache, and keeps none unless the binary gives it a folder
(cli/shader_cache_folder.h). The scratch folder is opened to that user; the binaries and scenes
must be readable by it.

Usage: scripts/bench_ab.py --bin NEW --baseline OLD [--rounds N] [--repeat N] [--scenes a,b]
                           [--filter F] [--size WxH] [--peers DIR] [--idle S] [--no-steady]
                           [--cold] [--outputs "ARGS"] [--user UID] [--hog MB]
                           [--hog-wait S]"""
import argparse, os, shutil, statistics, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_peers import load_compare, run_omni  # noqa: E402


def hog(megabytes, wait_s):
    """A process that fills `megabytes` of fresh memory and exits; then `wait_s` seconds."""
    subprocess.run([sys.executable, "-c",
                    f"b = bytearray(b'\\x01') * ({megabytes} << 20); print(b[-1])"],
                   check=True, capture_output=True)
    time.sleep(wait_s)


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", required=True, help="the omnishadow to measure")
    ap.add_argument("--baseline", required=True, help="the omnishadow to compare it with")
    ap.add_argument("--peers", default=os.path.join(root, "..", "shared", "peers"))
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=10, help="frames timed by render --repeat")
    ap.add_argument("--scenes", default="box,cornell,sundial,whackamole,test_room")
    ap.add_argument("--filter", default="pcf")
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--idle", type=float, default=0.0, help="seconds of sleep before each process")
    ap.add_argument("--no-steady", action="store_true", help="no render --repeat processes")
    ap.add_argument("--outputs", default="", help='render arguments for more outputs; {tmp}: a '
                    'scratch folder, e.g. "--masks {tmp}/m"')
    ap.add_argument("--cold", action="store_true",
                    help="also a single render with an empty shader cache per scene and binary")
    ap.add_argument("--user", type=int, help="run every process as this user id (needs root)")
    ap.add_argument("--hog", type=int, default=0,
                    help="MB a process fills and frees before each single render")
    ap.add_argument("--hog-wait", type=float, default=0.5,
                    help="seconds between the hog's exit and the render")
    a = ap.parse_args()
    wrapper = []
    if a.user is not None:
        if os.geteuid() != 0:
            sys.exit("bench_ab: --user needs root (setpriv changes the user)")
        wrapper = ["setpriv", "--reuid", str(a.user), "--regid", str(a.user), "--clear-groups"]
    if not os.path.isfile(os.path.join(a.peers, "compare.py")):
        sys.exit(f"bench_ab: no compare.py in {a.peers} (--peers DIR)")
    cmp = load_compare(a.peers)
    w, h = map(int, a.size.split("x"))
    tmp = tempfile.mkdtemp(prefix="bench-ab.")
    if wrapper:
        os.chmod(tmp, 0o1777)  # the user's outputs and shader caches go here
    extra = [arg.replace("{tmp}", tmp) for arg in a.outputs.split()]
    scenes = a.scenes.split(",")
    binaries = [("new", a.bin), ("baseline", a.baseline)]
    res = {}
    for r in range(a.rounds):
        order = binaries if r % 2 == 0 else binaries[::-1]
        for name in scenes:
            scene, lights = cmp["SCENES"][name]
            lf = cmp["with_filter"](lights, a.filter, tmp)
            for who, binary in order:
                out = f"{tmp}/{name}.{who}.png"
                steady = {}
                if not a.no_steady:
                    time.sleep(a.idle)
                    steady = run_omni(binary, scene, lf, out, w, h, a.repeat, extra=extra,
                                      wrapper=wrapper)
                time.sleep(a.idle)
                if a.hog:
                    hog(a.hog, a.hog_wait)
                first = run_omni(binary, scene, lf, out, w, h, 0, extra=extra, wrapper=wrapper)
                cold = {}
                if a.cold:
                    cache = tempfile.mkdtemp(prefix="shader-cache.", dir=tmp)
                    if wrapper:
                        os.chmod(cache, 0o1777)
                    time.sleep(a.idle)
                    if a.hog:
                        hog(a.hog, a.hog_wait)
                    cold = run_omni(binary, scene, lf, out, w, h, 0,
                                    env=dict(os.environ, MESA_SHADER_CACHE_DIR=cache), extra=extra,
                                    wrapper=wrapper)
                    shutil.rmtree(cache)
                res.setdefault((name, who), []).append((steady, first, cold))
                print(f"# round {r} {name} {who} steady {steady.get('steady') or 0:.1f} "
                      f"first {first['first']:.1f} wall {first['wall']:.0f}"
                      + (f" cold first {cold['first']:.1f} wall {cold['wall']:.0f}" if cold else ""),
                      file=sys.stderr, flush=True)

    def med(name, who, pick):
        values = [pick(s, f, c) for s, f, c in res[(name, who)]]
        values = [v for v in values if v is not None]
        return f"{statistics.median(values):.1f}" if values else "-"

    cold_heads = " | cold first frame | cold shaders | cold process ms" if a.cold else ""
    print("| scene | binary | steady shadow maps | steady lighting | steady readback | steady layers "
          "| steady frame "
          "| first shadow maps | first lighting | first frame | first total | process ms"
          + cold_heads + " |")
    print("|---|---|" + "---:|" * (10 + (3 if a.cold else 0)))
    for name in scenes:
        for who, _ in binaries:
            cells = [med(name, who, lambda s, f, c, k=k: s.get(f"steady {k}"))
                     for k in ("shadow maps", "lighting", "readback", "layers", "frame")]
            cells += [med(name, who, lambda s, f, c: f.get("shadow maps")),
                      med(name, who, lambda s, f, c: f.get("lighting")),
                      med(name, who, lambda s, f, c: f["first"]),
                      med(name, who, lambda s, f, c: f.get("total")),
                      med(name, who, lambda s, f, c: f["wall"])]
            if a.cold:
                cells += [med(name, who, lambda s, f, c: c.get("first")),
                          med(name, who, lambda s, f, c: c.get("shaders")),
                          med(name, who, lambda s, f, c: c.get("wall"))]
            print(f"| {name} | {who} | " + " | ".join(cells) + " |")
    print(f"\n{a.filter}, {w}x{h}, 1024^2 shadow maps, {a.rounds} interleaved rounds, medians; "
          f"steady: `render --repeat {a.repeat}`; first: a single `render`"
          + (f"; {a.idle:g} s idle before each process" if a.idle else "")
          + (f"; a {a.hog} MB process {a.hog_wait:g} s before each single render" if a.hog
             else "")
          + ("; cold: a single `render` with an empty shader cache" if a.cold else "")
          + (f"; outputs `{a.outputs}`" if a.outputs else "")
          + (f"; every process as uid {a.user}" if wrapper else "") + ".")


if __name__ == "__main__":
    main()
