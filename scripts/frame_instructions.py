#!/usr/bin/env python3
"""Instructions per steady frame under valgrind: A/Bs the host's noise would hide (issue 19).

On this shared 2-core host a steady Sundial frame runs anywhere from 14 to 21 ms within
minutes, so wall-clock A/Bs (scripts/bench_ab.py) need 10-16 interleaved rounds to see a change
of half a millisecond. This script counts instead: it runs
each binary's `render --repeat A` and `render --repeat B` under callgrind (valgrind's
instruction counter; llvmpipe's JIT code included) on compare.py's scenes and lights, and
prints (count of B - count of A) / (B - A), the instructions one more steady frame executes,
split by where they run:
- `shaders`: llvmpipe's JIT code (fragment, vertex and triangle-setup functions);
- `llvmpipe`: the driver's C code (binning, rasterization, clears, the GL state);
- `memcpy/memset`: the C library's copies and fills (uploads, readbacks, wide-texel clears).
  valgrind runs a large copy's `rep movsb` one byte per instruction (100 copies of 1 MiB: 104.9
  M), so this column is nearer the bytes moved than the work: Sundial's 16-18 M are its frame's
  copies of 16-18 MB, whose halving (a half-float beauty) saved no time;
- `omnishadow`: this program (frame planning, culling, the CPU's sRGB encoding);
- `compiles`: LLVM (should be 0 in a steady frame; a warm-up process fills the shader cache);
- `other`: everything else.

The counts repeat where wall time does not (on Sundial the shaders' and the driver's to 0.01%
from run to run, the copies and fills to a few percent); but they are instructions, not time:
a cache miss, a wait for another thread or a page fault costs no instruction. Use them to see
what a change does to the work, then bench_ab.py or bench-peers.sh for what it does to the
time. A render under valgrind runs some 100 times slower (a Sundial process of --repeat 12:
about 2 minutes).

Usage: scripts/frame_instructions.py --bin NEW [--baseline OLD] [--scenes sundial,box]
                                     [--frames 2,12] [--filter pcf] [--size WxH] [--peers DIR]"""
import argparse, collections, os, re, shutil, subprocess, sys, tempfile
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_peers import load_compare  # noqa: E402

GROUPS = ("shaders", "llvmpipe", "memcpy/memset", "omnishadow", "compiles", "other")
# callgrind_annotate's lines: "1,234 (12.3%)  file:function [object]".
LINE = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)\[(.*)\]\s*$")


def group_of(function, obj, binary):
    name = os.path.basename(obj)
    if obj == "???":
        return "shaders"  # JIT code has no object file
    if "memcpy" in function or "memmove" in function or "memset" in function:
        return "memcpy/memset"
    if name == "swrast_dri.so" or name.startswith("libgallium"):
        return "llvmpipe"
    if name.startswith("libLLVM"):
        return "compiles"
    if os.path.realpath(obj) == os.path.realpath(binary) or name.startswith("libomnishadow"):
        return "omnishadow"
    return "other"


def counts(path, binary):
    out = subprocess.run(["callgrind_annotate", "--threshold=100", "--inclusive=no", path],
                         capture_output=True, text=True, check=True).stdout
    total = collections.Counter()
    for line in out.splitlines():
        m = LINE.match(line)
        if m and not m.group(2).startswith("PROGRAM TOTALS"):
            total[group_of(m.group(2), m.group(3), binary)] += int(m.group(1).replace(",", ""))
    return total


def callgrind(binary, scene, lights, repeat, size, tmp, tag):
    out = os.path.join(tmp, f"{tag}.{repeat}.callgrind")
    args = ["valgrind", "--tool=callgrind", "--smc-check=all-non-file",
            f"--callgrind-out-file={out}", binary, "render", scene, "-l", lights,
            "-o", os.path.join(tmp, f"{tag}.{repeat}.png"), "--width", str(size[0]),
            "--height", str(size[1]), "--no-gltf-lights", "--repeat", str(repeat)]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{tag}: {p.stderr[-400:]}")
    return counts(out, binary)


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", required=True, help="the omnishadow to count")
    ap.add_argument("--baseline", help="another omnishadow, counted the same way")
    ap.add_argument("--peers", default=os.path.join(root, "..", "shared", "peers"))
    ap.add_argument("--scenes", default="sundial")
    ap.add_argument("--frames", default="2,12", help="the two --repeat values A,B (B > A)")
    ap.add_argument("--filter", default="pcf")
    ap.add_argument("--size", default="1280x720")
    a = ap.parse_args()
    if not shutil.which("valgrind") or not shutil.which("callgrind_annotate"):
        sys.exit("frame_instructions: needs valgrind (apt install valgrind)")
    if not os.path.isfile(os.path.join(a.peers, "compare.py")):
        sys.exit(f"frame_instructions: no compare.py in {a.peers} (--peers DIR)")
    few, many = map(int, a.frames.split(","))
    if many <= few:
        sys.exit("frame_instructions: --frames A,B needs B > A")
    size = tuple(map(int, a.size.split("x")))
    cmp = load_compare(a.peers)
    tmp = tempfile.mkdtemp(prefix="frame-instructions.")
    binaries = [("new", a.bin)] + ([("baseline", a.baseline)] if a.baseline else [])
    rows = []
    for name in a.scenes.split(","):
        scene, lights = cmp["SCENES"][name]
        lf = cmp["with_filter"](lights, a.filter, tmp)
        for who, binary in binaries:
            # A render first, so that the counted ones find their shaders in Mesa's cache. Under
            # valgrind: its CPUID is not the machine's, and llvmpipe's cache keys hold the CPU's
            # features, so a native render would leave the counted ones compiling (and whichever
            # of the two compiled would count llvmpipe's IR building as frame work).
            subprocess.run(["valgrind", "--tool=none", "--smc-check=all-non-file", binary, "render",
                            scene, "-l", lf, "-o", os.path.join(tmp, "warm.png"), "--width",
                            str(size[0]), "--height", str(size[1]), "--no-gltf-lights"],
                           capture_output=True, check=True)
        jobs = {}
        with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            for who, binary in binaries:
                for repeat in (few, many):
                    jobs[(who, repeat)] = pool.submit(callgrind, binary, scene, lf, repeat, size,
                                                      tmp, f"{name}.{who}")
        for who, _ in binaries:
            lo, hi = jobs[(who, few)].result(), jobs[(who, many)].result()
            per = {g: (hi[g] - lo[g]) / (many - few) / 1e6 for g in GROUPS}
            rows.append((name, who, per))
            print(f"# {name} {who}: " + ", ".join(f"{g} {per[g]:.2f}" for g in GROUPS),
                  file=sys.stderr, flush=True)
    print("| scene | binary | " + " | ".join(GROUPS) + " | total |")
    print("|---|---|" + "---:|" * (len(GROUPS) + 1))
    for name, who, per in rows:
        print(f"| {name} | {who} | " + " | ".join(f"{per[g]:.2f}" for g in GROUPS)
              + f" | {sum(per.values()):.2f} |")
    print(f"\nMillions of instructions per steady frame (callgrind, `render --repeat {many}` minus "
          f"`--repeat {few}`, over {many - few} frames); {a.filter}, {size[0]}x{size[1]}, "
          "compare.py's lights.")
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
