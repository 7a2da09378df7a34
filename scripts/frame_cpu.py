#!/usr/bin/env python3
"""CPU per steady frame, by thread, and the frame's floor on this machine's cores (issue 19).

Where bench_ab.py and bench-peers.sh time a frame's stages, this counts what the frame costs in
CPU and where: `perf record` samples every thread of a `render --repeat N` process (cpu-clock),
and uprobes on Renderer::Impl::renderShadows (a frame's start) and on the entry and return of
Renderer::Impl::drawImages (the lighting pass begins; the readback has ended) cut the samples
into frames. The process's first two frames are left out (shader variants, fresh memory). Per scene it
prints the frame's wall time under perf, the CPU of the calling thread, of llvmpipe's
rasterizer threads (threads named llvmpipe-N) and of the second shadow context's thread
(omni-shadows, renderer/passes/shadow_worker.h), the same split for the shadow stage and for the
lighting pass with its readback, and the floor: the CPU over the cores, the frame if every core
were busy from its first microsecond to its last. perf's sampling lengthens the frames, so the
ratio floor / frame is what carries over to frames timed without it.

Needs perf (Debian's linux-perf) with uprobes: root, or perf_event_paranoid <= 1 and access to
/sys/kernel/tracing. The probes are made in the group `omni_frame_cpu` and removed at the end.

With --timeline N it also draws N steady frames per scene as a timeline: one row per thread, one
character per 0.5 ms, from blank (idle) to # (busy the whole bin), so that the stretches where a
core idles beside a busy one show (docs/performance.md). Run it with --freq 10000 or more.

Usage: scripts/frame_cpu.py [--bin FILE] [--scenes a,b] [--repeat N] [--freq HZ] [--filter F]
                            [--size WxH] [--peers DIR] [--timeline N]"""
import argparse, bisect, collections, os, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_peers import load_compare  # noqa: E402
import perf_events  # noqa: E402

GROUP = "omni_frame_cpu"
WORKER_THREAD = "omni-shadows"  # ShadowWorker::kThreadName: the second shadow context's thread
FUNCTIONS = {  # probe name -> the function (omnishadow::<name>) it marks
    "frame": "Renderer::Impl::renderShadows",
    "lighting": "Renderer::Impl::drawImages",
}


def function_address(binary, name):
    found = perf_events.function_addresses(binary, name)
    if len(found) != 1:
        sys.exit(f"frame_cpu: {binary}: expected one function omnishadow::{name}, found "
                 f"{len(found)} (a stripped binary has no symbols)")
    return "0x" + found[0]


def add_probes(binary):
    remove_probes()
    frame = function_address(binary, FUNCTIONS["frame"])
    lighting = function_address(binary, FUNCTIONS["lighting"])
    perf_events.add_probes("frame_cpu", binary, [f"{GROUP}:frame={frame}",
                                                 f"{GROUP}:lighting={lighting}",
                                                 f"{GROUP}:done={lighting}%return"])


def remove_probes():
    perf_events.remove_probes(GROUP)


def record(binary, scene, lights, size, repeat, freq, tmp):
    w, h = size
    return perf_events.record_events(
        "frame_cpu", ["-e", "cpu-clock", "-F", str(freq), "-e", f"{GROUP}:*"],
        os.path.join(tmp, "perf.data"),
        [binary, "render", scene, "-l", lights, "-o", os.path.join(tmp, "frame.png"), "--width",
         str(w), "--height", str(h), "--no-gltf-lights", "--repeat", str(repeat)])


def frames_of(events):
    """(start, lighting, end) of each frame, in seconds, the first two left out."""
    frames, current = [], None
    for _, _, _, t, event in events:
        name = event.split(":", 1)[1] if event.startswith(GROUP) else None
        if name == "frame":
            current = [t, None]
        elif name == "lighting" and current:
            current[1] = t
        elif name == "done__return" and current and current[1] is not None:  # perf's name
            frames.append((current[0], current[1], t))
            current = None
    return frames[2:]


def measure(events, freq):
    frames = frames_of(events)
    if not frames:
        sys.exit("frame_cpu: no frame between the probes (is --repeat at least 3?)")
    starts = [f[0] for f in frames]
    cpu = collections.Counter()
    for comm, pid, tid, t, event in events:
        if not event.startswith("cpu-clock"):
            continue
        i = bisect.bisect_right(starts, t) - 1
        if i < 0 or t > frames[i][2]:
            continue
        stage = "shadow" if t < frames[i][1] else "lighting"
        who = ("calling" if tid == pid else "raster" if comm.startswith("llvmpipe") else
               "worker" if comm == WORKER_THREAD else "other")
        cpu[(stage, who)] += 1
    n = len(frames)
    ms = lambda samples: samples / freq * 1000 / n  # noqa: E731
    wall = {"shadow": sum(b - a for a, b, _ in frames) * 1000 / n,
            "lighting": sum(c - b for _, b, c in frames) * 1000 / n}
    r = {"frames": n, "wall": wall["shadow"] + wall["lighting"]}
    for stage in ("shadow", "lighting"):
        r[f"{stage} wall"] = wall[stage]
        for who in ("calling", "raster", "worker", "other"):
            r[f"{stage} {who}"] = ms(cpu[(stage, who)])
    for who in ("calling", "raster", "worker", "other"):
        r[who] = r[f"shadow {who}"] + r[f"lighting {who}"]
    return r


def timeline(events, freq, count, bin_ms=0.5):
    """Rows of characters, one per thread and bin of bin_ms, for `count` steady frames from the
    middle of the run; `|` marks the lighting pass's start."""
    frames = frames_of(events)
    middle = max(0, len(frames) // 2 - count // 2)
    shades = " .:-=+*#"
    per_bin = freq * bin_ms / 1000.0  # samples of a thread busy through a bin
    lines = []
    for start, lighting, end in frames[middle:middle + count]:
        bins = int((end - start) * 1000 / bin_ms) + 1
        rows = collections.defaultdict(lambda: [0] * bins)
        for comm, pid, tid, t, event in events:
            if event.startswith("cpu-clock") and start <= t <= end:
                who = ("calling" if tid == pid else comm if comm.startswith("llvmpipe") or
                       comm == WORKER_THREAD else f"other {tid}")
                rows[who][int((t - start) * 1000 / bin_ms)] += 1
        mark = int((lighting - start) * 1000 / bin_ms)
        lines.append(f"frame of {(end - start) * 1000:.1f} ms, lighting from "
                     f"{(lighting - start) * 1000:.1f} ms (|):")
        for who in sorted(rows):
            cells = [shades[min(len(shades) - 1, round(c / per_bin * (len(shades) - 1)))]
                     for c in rows[who]]
            cells.insert(mark, "|")
            lines.append(f"  {who:14} {''.join(cells)}")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    perf_events.add_scene_arguments(ap)
    ap.add_argument("--repeat", type=int, default=20, help="frames of render --repeat")
    ap.add_argument("--freq", type=int, default=4000, help="samples per second and thread")
    ap.add_argument("--timeline", type=int, default=0, metavar="N",
                    help="also draw N steady frames per scene as a per-thread timeline")
    a = ap.parse_args()
    if a.repeat < 3:
        sys.exit("frame_cpu: --repeat must be at least 3 (the first two frames are left out)")
    if not os.path.isfile(os.path.join(a.peers, "compare.py")):
        sys.exit(f"frame_cpu: no compare.py in {a.peers} (--peers DIR)")
    binary = os.path.abspath(a.bin)
    cores = os.cpu_count() or 1
    size = tuple(map(int, a.size.split("x")))
    cmp = load_compare(a.peers)
    rows, timelines = [], []
    with tempfile.TemporaryDirectory(prefix="frame-cpu.") as tmp:
        add_probes(binary)
        try:
            for name in a.scenes.split(","):
                scene, lights = cmp["SCENES"][name]
                lights = cmp["with_filter"](lights, a.filter, tmp)
                events = record(binary, scene, lights, size, a.repeat, a.freq, tmp)
                r = measure(events, a.freq)
                rows.append((name, r))
                if a.timeline:
                    timelines += [f"{name}:"] + timeline(events, a.freq, a.timeline)
                print(f"# {name}: {r['frames']} frames, {r['wall']:.1f} ms each under perf",
                      file=sys.stderr)
        finally:
            remove_probes()
    print(f"| scene | frame under perf ms | calling thread CPU | rasterizer threads CPU | "
          f"second shadow context CPU | other threads CPU | floor (CPU / {cores} cores) | floor / frame | shadow "
          f"stage: wall, calling, rasterizers, second context | lighting + readback: wall, "
          f"calling, rasterizers |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|---|")
    for name, r in rows:
        floor = (r["calling"] + r["raster"] + r["worker"] + r["other"]) / cores
        print(f"| {name} | {r['wall']:.1f} | {r['calling']:.1f} | {r['raster']:.1f} | "
              f"{r['worker']:.1f} | {r['other']:.1f} | {floor:.1f} | {floor / r['wall']:.2f} | "
              f"{r['shadow wall']:.1f}, {r['shadow calling']:.1f}, {r['shadow raster']:.1f}, "
              f"{r['shadow worker']:.1f} | {r['lighting wall']:.1f}, "
              f"{r['lighting calling']:.1f}, {r['lighting raster']:.1f} |")
    print(f"\n{a.filter}, {a.size}, `render --repeat {a.repeat}` (its {a.repeat + 1} frames "
          f"less the first two), cpu-clock at {a.freq} Hz; CPU in ms per frame. Other threads: "
          f"the readback's encoding thread and the memory warm-up.")
    if timelines:
        print("\nSteady frames, CPU per thread in 0.5 ms bins (blank: idle, #: busy throughout):")
        print("```")
        print("\n".join(timelines))
        print("```")


if __name__ == "__main__":
    main()
