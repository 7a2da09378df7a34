#!/usr/bin/env python3
"""Where a process's first frame goes, call by call, and who faults its fresh pages (issue 19).

Runs single `render`s of the bench scenes (compare.py's lights and settings) under perf with
uprobes on the entry and return of the renderer's functions named below, and prints each
function's time per render (the sum of its calls, min / median / max over the renders). A second
set of renders counts page faults (`page-faults -c 1`) per thread and stage: before the frame,
the shadow stage (Renderer::Impl::renderShadows), the lighting pass with its readback
(Renderer::Impl::drawImages). A first frame that faults on its calling thread is waiting for
the kernel to hand it fresh memory that the memory warm-up (cli/memory_warmup.h) did not reach in
time; the warm-up's own faults in the same stage show it still racing the frame.

Needs perf with uprobes (root, or perf_event_paranoid <= 1). The probes are made in the group
`omni_first_frame` and removed at the end.

Usage: scripts/first_frame_calls.py [--bin FILE] [--scenes a,b] [--renders N] [--calls A,B]
                                    [--filter F] [--size WxH] [--peers DIR]"""
import argparse, collections, os, statistics, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_peers import load_compare  # noqa: E402
import perf_events  # noqa: E402

GROUP = "omni_first_frame"
CALLS = ("Renderer::Impl::renderShadows,ShadowTexturePool::take,TransmittancePass::place,"
         "ShadowPass::render,TransmittancePass::render,TransmittancePass::attachTarget,"
         "Renderer::Impl::drawImages,FrameTargets::FrameTargets,readSrgb8InBands")
STAGE_CALLS = ("Renderer::Impl::renderShadows", "Renderer::Impl::drawImages")


def add_probes(binary, calls):
    """Probes p<k>_<j> (entry and %return) for each overload j of calls[k]."""
    names, specs = {}, []
    for k, call in enumerate(calls):
        addresses = perf_events.function_addresses(binary, call)
        if not addresses:
            sys.exit(f"first_frame_calls: no function omnishadow::{call} in {binary}")
        for j, address in enumerate(addresses):
            event = f"p{k}_{j}"
            names[event] = call
            specs += [f"{GROUP}:{event}=0x{address}", f"{GROUP}:{event}=0x{address}%return"]
    perf_events.add_probes("first_frame_calls", binary, specs)
    return names


def remove_probes():
    perf_events.remove_probes(GROUP)


def record(binary, scene, lights, size, tmp, extra_events=()):
    w, h = size
    return perf_events.record_events(
        "first_frame_calls", [*extra_events, "-e", f"{GROUP}:*"], os.path.join(tmp, "perf.data"),
        [binary, "render", scene, "-l", lights, "-o", os.path.join(tmp, "frame.png"), "--width",
         str(w), "--height", str(h), "--no-gltf-lights"])


def call_times(events, names):
    """Milliseconds per call name: the sum of its outermost calls on each thread."""
    depth, since, total = collections.Counter(), {}, collections.Counter()
    for _, _, tid, t, event in events:
        if not event.startswith(GROUP + ":"):
            continue
        probe = event.split(":", 1)[1]
        returning = probe.endswith("__return")
        call = names[probe.removesuffix("__return")]
        key = (tid, call)
        if not returning:
            if depth[key] == 0:
                since[key] = t
            depth[key] += 1
        elif depth[key] > 0:
            depth[key] -= 1
            if depth[key] == 0:
                total[call] += (t - since.pop(key)) * 1000
    return total


def stage_faults(events, names):
    """Page faults per (stage, thread kind) of the first frame."""
    marks = {}
    for _, pid, tid, t, event in events:
        if event.startswith(GROUP + ":") and tid == pid:
            probe = event.split(":", 1)[1]
            call = names[probe.removesuffix("__return")]
            key = (call, probe.endswith("__return"))
            marks.setdefault(key, t)
    shadow = marks.get((STAGE_CALLS[0], False))
    lighting = marks.get((STAGE_CALLS[1], False))
    done = marks.get((STAGE_CALLS[1], True))
    counts = collections.Counter()
    if None in (shadow, lighting, done):
        return counts
    for comm, pid, tid, t, event in events:
        if event != "page-faults":
            continue
        stage = ("before" if t < shadow else "shadow" if t < lighting else
                 "lighting" if t < done else "after")
        who = "calling" if tid == pid else "llvmpipe" if comm.startswith("llvmpipe") else "other"
        counts[(stage, who)] += 1
    return counts


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    perf_events.add_scene_arguments(ap)
    ap.add_argument("--renders", type=int, default=7, help="single renders per scene and set")
    ap.add_argument("--calls", default=CALLS, help="functions (omnishadow::<name>) to time")
    a = ap.parse_args()
    if not os.path.isfile(os.path.join(a.peers, "compare.py")):
        sys.exit(f"first_frame_calls: no compare.py in {a.peers} (--peers DIR)")
    calls = a.calls.split(",")
    for needed in STAGE_CALLS:
        if needed not in calls:
            calls.append(needed)
    binary = os.path.abspath(a.bin)
    size = tuple(map(int, a.size.split("x")))
    cmp = load_compare(a.peers)
    times, faults = {}, {}
    remove_probes()
    names = add_probes(binary, calls)
    try:
        with tempfile.TemporaryDirectory(prefix="first-frame.") as tmp:
            for scene_name in a.scenes.split(","):
                scene, lights = cmp["SCENES"][scene_name]
                lights = cmp["with_filter"](lights, a.filter, tmp)
                times[scene_name] = [call_times(record(binary, scene, lights, size, tmp), names)
                                     for _ in range(a.renders)]
                faults[scene_name] = [
                    stage_faults(record(binary, scene, lights, size, tmp,
                                        ("-e", "page-faults", "-c", "1")), names)
                    for _ in range(a.renders)]
                print(f"# {scene_name}: {a.renders} + {a.renders} renders", file=sys.stderr)
    finally:
        remove_probes()
    fmt = lambda values: (f"{min(values):.1f} / {statistics.median(values):.1f} / "  # noqa: E731
                          f"{max(values):.1f}")
    print(f"Calls of a first frame, ms per render (min / median / max of {a.renders}; a call "
          "inside another counts in both):\n")
    print("| call | " + " | ".join(times) + " |")
    print("|---|" + "---:|" * len(times))
    for call in calls:
        cells = []
        for runs in times.values():
            values = [run.get(call, 0.0) for run in runs]
            cells.append(fmt(values) if any(values) else "-")
        print(f"| `{call}` | " + " | ".join(cells) + " |")
    print(f"\nPage faults of a first frame per stage and thread (min / median / max of "
          f"{a.renders}; 4 KiB pages, or one per huge page):\n")
    print("| stage, thread | " + " | ".join(faults) + " |")
    print("|---|" + "---:|" * len(faults))
    for stage in ("before", "shadow", "lighting"):
        for who in ("calling", "llvmpipe", "other"):
            cells = []
            for runs in faults.values():
                values = [run.get((stage, who), 0) for run in runs]
                cells.append(f"{min(values)} / {statistics.median(values):.0f} / {max(values)}")
            print(f"| {stage}, {who} | " + " | ".join(cells) + " |")
    print(f"\n{a.filter}, {a.size}, single `render`s; stages split at "
          "Renderer::Impl::renderShadows and drawImages; `other` is mostly the memory warm-up's "
          "toucher and the loader.")


if __name__ == "__main__":
    main()
