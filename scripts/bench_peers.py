#!/usr/bin/env python3
"""omnishadow against three.js r187 on the same llvmpipe, interleaved (scripts/bench-peers.sh).

Reuses ../shared/peers/compare.py's scene table and runners (its functions are loaded, its
main() is not run) and adds what the issue's targets need: omnishadow's steady-state frame
(`render --repeat`), its first frame, and an optional baseline binary measured in the same
rounds for before/after. Prints a markdown table and writes it to OUT/peers.md."""
import argparse, os, re, statistics, subprocess, sys, tempfile, time


def load_compare(peers):
    path = os.path.join(peers, "compare.py")
    source = open(path).read()
    source = source[: source.rindex("\nmain()")]  # the functions only
    namespace = {"__file__": path, "__name__": "compare"}
    exec(compile(source, path, "exec"), namespace)
    return namespace


def settle(limit_s=5.0, after_s=2.0):
    """Waits until no Chromium process is left (at most limit_s), then after_s: node returns
    while Chromium's processes still exit and hand their memory back, and a process started then
    ran up to twice as long (Sundial 234-407 against 141-175 ms in one run). The host then takes
    back the memory Chromium freed (virtio-balloon's free page reporting, cli/huge_page_trial.h),
    and a process that faults fresh pages within a second or so pays for the host backing them
    again: with one binary in both of bench-peers' places, 6 rounds, Sundial's steady frame was
    19.9 ms right after three.js against 17.9 one process later with a quarter second's wait,
    17.9 against 18.4 with 2 s."""
    end = time.time() + limit_s
    while time.time() < end:
        if subprocess.run(["pgrep", "-x", "chromium"], capture_output=True).returncode != 0:
            break
        time.sleep(0.05)
    time.sleep(after_s)


def run_omni(binary, scene, lights, out, w, h, repeat, env=None, extra=(), wrapper=()):
    """One `render` process (`wrapper`: a command it runs under, e.g. setpriv)."""
    args = [*wrapper, binary, "render", scene, "-l", lights, "-o", out, "--width", str(w), "--height", str(h),
            "--no-gltf-lights", "--stats", *extra]
    if repeat:
        args += ["--repeat", str(repeat)]
    t0 = time.time()
    p = subprocess.run(args, capture_output=True, text=True, timeout=900, env=env)
    wall = (time.time() - t0) * 1000
    if p.returncode != 0:
        raise RuntimeError(p.stderr[-400:])
    st = {}
    for line in p.stderr.splitlines():
        m = re.match(r"^(\w[\w ]*?)\s+([\d.]+)$", line.strip())
        if m:
            st[m.group(1)] = st.get(m.group(1), 0) + float(m.group(2))
    # The stages `steady frame` sums (cli/steady_frames.cpp).
    first = sum(st.get(k, 0) for k in ("shadow maps", "lighting", "readback", "layers", "light views"))
    return {"wall": wall, "first": first, "steady": st.get("steady frame"), **st}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    ap.add_argument("--baseline", help="another omnishadow binary, measured in the same rounds")
    ap.add_argument("--peers", required=True)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--repeat", type=int, default=10, help="frames timed by render --repeat")
    ap.add_argument("--scenes", default="box,cornell,sundial,whackamole,test_room")
    ap.add_argument("--filter", default="pcf")
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    cmp = load_compare(a.peers)
    w, h = map(int, a.size.split("x"))
    tmp = tempfile.mkdtemp(prefix="bench-peers.")
    os.makedirs(a.out, exist_ok=True)
    scenes = a.scenes.split(",")
    ours = [("omni", a.bin), ("steady", a.bin)]
    if a.baseline:
        ours += [("baseline", a.baseline), ("baseline-steady", a.baseline)]
        # The process right after three.js is the slower one (80-180 ms more wall time for Box in
        # one run, settle() notwithstanding): each binary takes that turn equally often, or the
        # medians would favour the one that took it less.
        if a.rounds % 2:
            a.rounds += 1
            print(f"# rounds raised to {a.rounds}: with a baseline, an even number",
                  file=sys.stderr)
    res = {}
    for r in range(a.rounds):
        # three.js first, then settle(); the binaries still take turns at running right after
        # it, in case anything else of Chromium's lingers.
        turn = (2 * r) % len(ours)
        runners = [("three", None)] + ours[turn:] + ours[:turn]
        for name in scenes:
            scene, lights = cmp["SCENES"][name]
            lf = cmp["with_filter"](lights, a.filter, tmp)
            for who, binary in runners:
                try:
                    if who == "three":
                        x = cmp["run_three"](scene, lf, f"{tmp}/{name}.three.png", w, h, a.filter)
                        settle()
                    else:
                        x = run_omni(binary, scene, lf, f"{tmp}/{name}.{who}.png", w, h,
                                     a.repeat if who.endswith("steady") else 0)
                except Exception as e:  # reported, not fatal: the table says "missing"
                    print(f"# {name} {who} failed: {e}", file=sys.stderr)
                    continue
                res.setdefault((name, who), []).append(x)
                print(f"# round {r} {name} {who} wall {x['wall']:.0f} "
                      f"frame {x.get('frame', x.get('steady') or x.get('first', 0)):.1f}",
                      file=sys.stderr, flush=True)

    def med(name, who, key):
        xs = [x[key] for x in res.get((name, who), []) if x.get(key) is not None]
        return statistics.median(xs) if xs else None

    def f(v, fmt="{:.0f}"):
        return "-" if v is None else fmt.format(v)

    def ratio(x, y):
        return "-" if x is None or y is None or y == 0 else f"{x / y:.2f}"

    lines = ["| scene | three.js process ms | omnishadow process ms | process ratio (target <= 0.1) "
             "| three.js steady frame ms | omnishadow steady frame ms | steady ratio (target <= 0.5) "
             "| omnishadow first frame ms | first / three.js steady (target <= 1) |"
             + (" baseline process ms | baseline first frame ms | baseline steady frame ms |"
                if a.baseline else ""),
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|---:|---:|" if a.baseline else "")]
    for name in scenes:
        tw, ow = med(name, "three", "wall"), med(name, "omni", "wall")
        tf, of = med(name, "three", "frame"), med(name, "steady", "steady")
        first = med(name, "omni", "first")
        row = (f"| {name} | {f(tw)} | {f(ow)} | {ratio(ow, tw)} | {f(tf, '{:.1f}')} | "
               f"{f(of, '{:.1f}')} | {ratio(of, tf)} | {f(first, '{:.1f}')} | {ratio(first, tf)} |")
        if a.baseline:
            row += (f" {f(med(name, 'baseline', 'wall'))} | "
                    f"{f(med(name, 'baseline', 'first'), '{:.1f}')} | "
                    f"{f(med(name, 'baseline-steady', 'steady'), '{:.1f}')} |")
        lines.append(row)
    note = (f"\n{a.filter}, {w}x{h}, 1024^2 shadow maps, {a.rounds} interleaved rounds, medians; "
            f"omnishadow steady frame: median of `render --repeat {a.repeat}` (shadow maps + lighting + "
            "readback); first frame: the same stages of a single `render` process; three.js frame: "
            "its steady-state median (compare.py).")
    table = "\n".join(lines) + "\n" + note + "\n"
    print(table)
    with open(os.path.join(a.out, "peers.md"), "w") as out:
        out.write(table)


if __name__ == "__main__":
    main()
