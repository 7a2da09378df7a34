#!/usr/bin/env python3
"""Runs the shadow benchmarks for scripts/bench-shadows.sh (which builds the binaries and calls
this with their paths). Standard library only. Not a test: numbers only.

Generates the scenes (make_shadow_bench_scene, reproducible by seed), renders each configuration
with `omnishadow render --stats` under /usr/bin/time -v in interleaved rounds (configuration A,
B, C, A, B, C, ... so the noise of a shared machine hits every configuration alike), writes one
CSV row per run, prints median tables, and draws a 2x2 plot with gnuplot when it is installed.
"""
import argparse
import csv
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

STRATEGIES = ["six", "geometry", "instanced", "auto"]
SCENARIOS = ["strategies", "lights", "triangles", "resolution"]
ALIASES = {"1": "strategies", "2": "lights", "3": "triangles", "4": "resolution"}
STAGE_COLUMNS = ["load", "context", "shaders", "upload", "shadow", "lighting", "readback", "encode"]
CSV_COLUMNS = (["scenario", "parameter", "strategy", "run", "triangles", "lights", "resolution",
                "range_m", "width", "height"] + [s + "_ms" for s in STAGE_COLUMNS] +
               ["other_ms", "total_ms", "wall_ms", "rss_mib", "status", "note"])


def plan(quick, scenarios, has_shadow_pass):
    """Configurations per scenario: dicts with triangles, lights, resolution, strategy, param."""
    if quick:
        base = dict(triangles=50000, lights=4, resolution=256)
        lights, lights_res = [1, 4, 16, 64, 256], 128
        triangles = [10000, 50000, 250000]
        resolutions = [256, 512, 1024]
    else:
        base = dict(triangles=250000, lights=4, resolution=1024)
        lights, lights_res = [1, 4, 16, 64, 256], 512
        triangles = [10000, 50000, 250000, 1000000, 2000000]
        resolutions = [256, 512, 1024, 2048, 4096]
    out = {}
    for s in scenarios:
        if s == "strategies":
            strategies = STRATEGIES if has_shadow_pass else ["default"]
            out[s] = [dict(base, strategy=st, param=st) for st in strategies]
        elif s == "lights":
            out[s] = [dict(base, lights=n, resolution=lights_res, strategy="default", param=n)
                      for n in lights]
        elif s == "triangles":
            out[s] = [dict(base, triangles=t, strategy="default", param=t) for t in triangles]
        elif s == "resolution":
            out[s] = [dict(base, resolution=r, strategy="default", param=r) for r in resolutions]
    return out


def shadow_mib(c):
    return c["lights"] * 6 * 4 * c["resolution"] ** 2 / 2 ** 20


def parse_run(text):
    """Stage times (the --stats lines, parsed as scripts/bench-demo.sh does), wall s, RSS KiB."""
    stages = {}
    for name, ms in re.findall(r"^(\w[\w ]*?)\s+([\d.]+)$", text, re.M):
        stages[name] = stages.get(name, 0.0) + float(ms)
    m = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", text)
    wall = int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3)) if m else None
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    rss = int(m.group(1)) if m else None
    return stages, wall, rss


def stage_column(name):
    name = name.lower()
    if name.startswith("shadow"):
        return "shadow"
    for s in STAGE_COLUMNS:
        if name.startswith(s):
            return s
    return None


def fmt(v, digits=1):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    return f"{v:.{digits}f}"


def human(n):
    if n >= 1000000 and n % 1000000 == 0:
        return f"{n // 1000000}M"
    if n >= 1000 and n % 1000 == 0:
        return f"{n // 1000}k"
    return str(n)


class Bench:
    def __init__(self, args, rows=None):
        self.args = args
        self.work = tempfile.mkdtemp(prefix="bench-shadows.")
        self.scenes = {}  # (triangles, lights, resolution) -> (path, range_m, summary)
        self.rows = rows or []
        os.makedirs(args.out, exist_ok=True)
        self.csv_path = os.path.join(args.out, "shadows.csv")
        self.csv_file = None
        if rows is not None:  # --report-only: the runs come from the CSV
            return
        self.csv_file = open(self.csv_path, "w", newline="")
        self.csv = csv.DictWriter(self.csv_file, CSV_COLUMNS)
        self.csv.writeheader()

    def scene(self, c):
        key = (c["triangles"], c["lights"], c["resolution"])
        if key not in self.scenes:
            path = os.path.join(self.work, "room_t{}_l{}_r{}.gltf".format(*key))
            cmd = [self.args.gen, path, "--triangles", str(key[0]), "--lights", str(key[1]),
                   "--resolution", str(key[2]), "--seed", str(self.args.seed),
                   "--range", self.args.range, "--lights-per-point", str(self.args.lights_per_point)]
            summary = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip()
            m = re.search(r"range ([\d.]+) m", summary)
            self.scenes[key] = (path, float(m.group(1)) if m else None, summary)
            print("  scene: " + summary.split(": ", 1)[1], flush=True)
        return self.scenes[key]

    def render(self, c, scenario, run, record=True):
        path, range_m, _ = self.scene(c)
        tag = f"{scenario}_{c['param']}"
        image = os.path.join(self.work, tag + ".png")
        max_memory = max(4096, math.ceil(shadow_mib(c) * 1.5) + 256)
        cmd = ["/usr/bin/time", "-v", self.args.bin, "render", path, "-o", image, "--stats",
               "--width", str(self.args.width), "--height", str(self.args.height),
               "--max-memory", str(max_memory)]
        if c["strategy"] != "default":
            cmd += ["--shadow-pass", c["strategy"]]
        start = time.monotonic()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=self.args.timeout)
            text, rc = p.stdout + p.stderr, p.returncode
        except subprocess.TimeoutExpired as e:
            text, rc = (e.stdout or b"").decode() + (e.stderr or b"").decode(), "timeout"
        elapsed = time.monotonic() - start
        stages, wall, rss = parse_run(text)
        row = dict(scenario=scenario, parameter=c["param"], strategy=c["strategy"], run=run,
                   triangles=c["triangles"], lights=c["lights"], resolution=c["resolution"],
                   range_m="" if range_m is None else range_m, width=self.args.width,
                   height=self.args.height)
        other = 0.0
        total = stages.pop("total", None)  # printed by newer binaries; else the sum of the stages
        for name, ms in stages.items():
            col = stage_column(name)
            if col:
                row[col + "_ms"] = round(row.get(col + "_ms", 0.0) + ms, 2)
            else:
                other += ms
        row["other_ms"] = round(other, 2)
        row["total_ms"] = round(total if total is not None else sum(stages.values()), 2)
        row["wall_ms"] = round((wall if wall is not None else elapsed) * 1000, 1)
        row["rss_mib"] = round(rss / 1024, 1) if rss else ""
        if rc == 0:
            row["status"], row["note"] = "ok", ""
        else:
            lines = [l for l in text.splitlines() if l.startswith("omnishadow")] or \
                    [l for l in text.splitlines() if l.strip() and "Command" not in l][:1] or [""]
            row["status"] = "failed" if rc != "timeout" else "timeout"
            row["note"] = lines[-1][:200]
        if record:
            self.csv.writerow(row)
            self.csv_file.flush()
            self.rows.append(row)
        return row

    def run_scenario(self, scenario, configs):
        print(f"\n== {scenario}: {len(configs)} configurations x {self.args.runs} runs, "
              f"{self.args.width}x{self.args.height}", flush=True)
        for c in configs:
            self.scene(c)
        # One untimed render of each configuration first: the first processes after the scenes
        # are written run on a cold machine (in a run at df229c3 the first render's upload and
        # lighting took 45 and 230 ms against 24 and 165-178 in the rounds after it), whichever
        # configuration comes first.
        for c in configs[:1] * self.args.warmup:
            r = self.render(c, scenario, 0, record=False)
            print(f"  warm-up {str(c['param']):>9}: shadow {fmt(r.get('shadow_ms')):>8} ms"
                  f"  total {fmt(r.get('total_ms')):>8} ms (not counted)", flush=True)
        dead = set()
        for run in range(1, self.args.runs + 1):
            for c in configs:
                if c["param"] in dead:
                    continue
                r = self.render(c, scenario, run)
                if r["status"] != "ok":
                    dead.add(c["param"])  # same input, same failure: skip its other rounds
                    print(f"  run {run} {c['param']}: {r['status'].upper()}: {r['note']}",
                          flush=True)
                else:
                    print(f"  run {run} {str(c['param']):>9}: shadow {fmt(r.get('shadow_ms')):>8} ms"
                          f"  lighting {fmt(r.get('lighting_ms')):>8} ms  total {fmt(r['total_ms']):>8} ms"
                          f"  rss {fmt(r['rss_mib'], 0):>6} MiB", flush=True)

    # ---------------------------------------------------------------------------------------
    # Summaries

    def per_round_ratios(self, scenario):
        """Each strategy's shadow time over `geometry`'s in the same round."""
        by = {}
        for r in self.rows:
            if r["scenario"] == scenario and r["status"] == "ok" and r.get("shadow_ms"):
                by.setdefault(r["parameter"], {})[r["run"]] = float(r["shadow_ms"])
        base = by.get("geometry")
        if not base:
            return []
        lines = ["", "Shadow time over `geometry`'s in the same round, rounds in order:", ""]
        for p, runs in by.items():
            if p == "geometry":
                continue
            ratios = [runs[k] / base[k] for k in sorted(runs) if k in base]
            if ratios:
                lines.append(f"- {p}: " + ", ".join(f"{x:.2f}" for x in ratios) +
                             f" (largest {max(ratios):.2f})")
        return lines

    def medians(self, scenario):
        """param -> dict of medians over the ok runs, or {'failed': note}; in plan order."""
        out = {}
        for r in self.rows:
            if r["scenario"] != scenario:
                continue
            d = out.setdefault(r["parameter"], {"runs": [], "failed": None, "row": r})
            if r["status"] == "ok":
                d["runs"].append(r)
            else:
                d["failed"] = f"{r['status']}: {r['note']}"
        for d in out.values():
            ok = d["runs"]
            for col in [s + "_ms" for s in STAGE_COLUMNS] + ["total_ms", "wall_ms", "rss_mib"]:
                vals = [float(r[col]) for r in ok if r.get(col) not in (None, "")]
                d[col] = statistics.median(vals) if vals else None
        return out

    def table(self, scenario, med, label, extra=None):
        head = [label, "runs", "shadow maps", "lighting", "readback", "encode", "total",
                "wall", "peak RSS"] + ([extra[0]] if extra else [])
        lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for param, d in med.items():
            if not d["runs"]:
                cells = [human(param) if isinstance(param, int) else str(param), "0",
                         "failed"] + [""] * (len(head) - 3)
            else:
                cells = [human(param) if isinstance(param, int) else str(param), str(len(d["runs"])),
                         fmt(d["shadow_ms"]), fmt(d["lighting_ms"]), fmt(d["readback_ms"]),
                         fmt(d["encode_ms"]), fmt(d["total_ms"]), fmt(d["wall_ms"], 0),
                         fmt(d["rss_mib"], 0) + " MiB"]
                if extra:
                    cells.append(extra[1](param, d))
            lines.append("| " + " | ".join(cells) + " |")
        return lines

    def report(self, configs):
        a = self.args
        out = []
        out.append(f"Medians in ms (stage times from --stats; total = the binary's `total` stage (or the sum of the stages); wall from "
                   f"/usr/bin/time), {a.width}x{a.height}, seed {a.seed}, range {a.range} "
                   f"(about {a.lights_per_point} lights per point), {a.runs} run(s) each.")
        data = {}
        if "strategies" in configs:
            med = self.medians("strategies")
            c0 = configs["strategies"][0]
            out += ["", f"### (1) shadow pass strategies: {human(c0['triangles'])} triangles, "
                        f"{c0['lights']} point lights at {c0['resolution']}^2", ""]
            base = med.get("geometry", {}).get("shadow_ms")
            ratio = (lambda p, d: fmt(d["shadow_ms"] / base, 2) + "x" if base and d["shadow_ms"] else "-")
            out += self.table("strategies", med, "--shadow-pass", ("shadow / geometry", ratio))
            out += self.per_round_ratios("strategies")
            if not a.has_shadow_pass:
                out += ["", "This binary has no `--shadow-pass` option yet: only its default shadow "
                            "pass was measured."]
            else:
                images = [os.path.join(self.work, f"strategies_{s}.png") for s in med]
                blobs = {open(p, "rb").read() for p in images if os.path.exists(p)}
                if blobs:
                    out += ["", "Beauty images of all strategies byte-identical: " +
                            ("yes" if len(blobs) == 1 else f"NO ({len(blobs)} different images)")]
            data["strategies"] = [(p, d["shadow_ms"]) for p, d in med.items() if d["runs"]]
        if "lights" in configs:
            med = self.medians("lights")
            c0 = configs["lights"][0]
            out += ["", f"### (2) number of point lights: {human(c0['triangles'])} triangles, "
                        f"cube maps at {c0['resolution']}^2", ""]
            per = lambda p, d: fmt(d["shadow_ms"] / p, 2) if d["shadow_ms"] is not None else "-"
            rng = {r["parameter"]: r["range_m"] for r in self.rows if r["scenario"] == "lights"}
            out += self.table("lights", med, "lights",
                              ("shadow ms per light / range m",
                               lambda p, d: per(p, d) + " / " + (fmt(float(rng[p]), 2) if rng.get(p) else "none")))
            ok = [(p, d) for p, d in med.items() if d["runs"] and d["shadow_ms"]]
            out.append("")
            for key, name in (("shadow_ms", "shadow maps"), ("total_ms", "total")):
                if len(ok) >= 2:
                    (n0, d0), (n1, d1) = ok[0], ok[-1]
                    slope = math.log(d1[key] / d0[key]) / math.log(n1 / n0)
                    steps = [math.log(b[1][key] / a_[1][key]) / math.log(b[0] / a_[0])
                             for a_, b in zip(ok, ok[1:])]
                    verdict = "no worse than linear" if slope <= 1.05 else "WORSE THAN LINEAR"
                    out.append(f"Growth of {name} with lights: log-log slope {slope:.2f} from "
                               f"{n0} to {n1} lights (steps: " + ", ".join(f"{s:.2f}" for s in steps) +
                               f"): {verdict}.")

            data["lights"] = [(p, d["shadow_ms"], d["lighting_ms"], d["total_ms"]) for p, d in ok]
        if "triangles" in configs:
            med = self.medians("triangles")
            c0 = configs["triangles"][0]
            out += ["", f"### (3) triangles: {c0['lights']} point lights at {c0['resolution']}^2", ""]
            out += self.table("triangles", med, "triangles",
                              ("shadow ms per 100k triangles",
                               lambda p, d: fmt(d["shadow_ms"] / p * 1e5, 2) if d["shadow_ms"] else "-"))
            data["triangles"] = [(p, d["shadow_ms"], d["lighting_ms"], d["total_ms"])
                                 for p, d in med.items() if d["runs"]]
        if "resolution" in configs:
            med = self.medians("resolution")
            c0 = configs["resolution"][0]
            out += ["", f"### (4) cube map resolution: {human(c0['triangles'])} triangles, "
                        f"{c0['lights']} point lights", ""]
            out += self.table("resolution", med, "resolution",
                              ("shadow ns per texel",
                               lambda p, d: fmt(d["shadow_ms"] * 1e6 / (d_lights(c0) * 6 * p * p), 2)
                               if d["shadow_ms"] else "-"))
            data["resolution"] = [(p, d["shadow_ms"], d["lighting_ms"], d["total_ms"])
                                  for p, d in med.items() if d["runs"]]
        failures = {}
        for r in self.rows:
            if r["status"] != "ok":
                failures.setdefault(r["note"], []).append(f"{r['scenario']} {r['parameter']}")
        if failures:
            out += ["", "Failed runs:"]
            out += [f"- {', '.join(sorted(set(w)))}: `{note}`" for note, w in failures.items()]
        data["failed"] = {s: [r["parameter"] for r in self.rows
                              if r["scenario"] == s and r["status"] != "ok"] for s in configs}
        return out, data


def d_lights(c):
    return c["lights"]


def machine_lines(binary, scene):
    lines = []
    cpu = ""
    try:
        for l in open("/proc/cpuinfo"):
            if l.startswith("model name"):
                cpu = l.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for l in open("/proc/meminfo"):
            if l.startswith("MemTotal"):
                mem = f"{int(l.split()[1]) / 2 ** 20:.0f} GiB"
    except OSError:
        pass
    load = ""
    try:
        load = ", load average " + " ".join(open("/proc/loadavg").read().split()[:3]) + " at the start"
    except OSError:
        pass
    lines.append(f"CPU: {cpu or platform.processor()}, {os.cpu_count()} cores, {mem} RAM, "
                 f"{platform.system()} {platform.release()}{load}")
    try:
        with tempfile.TemporaryDirectory() as t:
            p = subprocess.run([binary, "render", scene, "-v", "-o", os.path.join(t, "v.png"),
                                "--width", "64", "--height", "36"], capture_output=True, text=True,
                               timeout=300)
        gl = [l.strip().removeprefix("omnishadow: ") for l in (p.stdout + p.stderr).splitlines()
              if l.startswith("omnishadow: ") and re.search(r"EGL|\|", l)]
        lines += ["GL: " + "; ".join(gl[:3])] if gl else []
    except (OSError, subprocess.SubprocessError):
        pass
    return lines


def plot(data, out_png, work, quick, title):
    gnuplot = shutil.which("gnuplot")
    if not gnuplot:
        print("gnuplot not found: no plot", file=sys.stderr)
        return False
    terms = subprocess.run([gnuplot, "-e", "set terminal"], capture_output=True, text=True)
    term = "pngcairo noenhanced size 1400,1000 font ',11'" \
        if "pngcairo" in terms.stdout + terms.stderr else "png noenhanced size 1400,1000"
    g = [f"set terminal {term}", f"set output '{out_png}'",
         f"set multiplot layout 2,2 title '{title}'",
         "set grid", "set datafile missing '-'"]

    def dat(name, rows):
        path = os.path.join(work, name + ".dat")
        with open(path, "w") as f:
            for r in rows:
                f.write(" ".join("-" if v is None else str(v) for v in r) + "\n")
        return path

    def empty(title):
        return [f"set title '{title}'", "unset logscale", "set xrange [0:1]", "set yrange [0:1]",
                "set label 1 'not run' at 0.5,0.5 center", "plot NaN notitle", "unset label 1",
                "set autoscale"]

    failed = data.get("failed", {})
    rows = data.get("strategies")
    if rows:
        base = dict(rows).get("geometry")
        labels = [f"{ms:.0f} ms" + (f" ({ms / base:.2f}x)" if base else "") for _, ms in rows]
        p = dat("strategies", [(f'"{s}"', ms, f'"{l}"') for (s, ms), l in zip(rows, labels)])
        sub = " (shadow / geometry)" if base else \
            (" (no --shadow-pass option: default only)" if [r[0] for r in rows] == ["default"] else "")
        g += [f"set title 'shadow maps per --shadow-pass, median ms{sub}'", "unset logscale",
              "set style fill solid 0.6", "set boxwidth 0.5", "set yrange [0:*]",
              f"set xrange [-0.7:{len(rows) - 0.3}]", "set key off",
              f"plot '{p}' using 0:2:xtic(1) with boxes lc rgb '#4477aa', "
              f"'' using 0:2:3 with labels offset 0,0.8",
              "set autoscale", "set xtics autofreq", "set key top left"]
    else:
        g += empty("shadow maps per --shadow-pass")
    panels = [("lights", "point lights", "time vs point lights (median ms, log-log)", 1.0, "linear"),
              ("triangles", "triangles", "time vs triangles (median ms, log-log)", 1.0, "linear"),
              ("resolution", "cube map resolution (texels per face edge)",
               "time vs cube map resolution (median ms, log-log)", 2.0, "~ resolution squared")]
    for key, xlabel, title, power, reflabel in panels:
        rows = data.get(key)
        if not rows:
            g += empty(title)
            continue
        p = dat(key, rows)
        xs = [r[0] for r in rows] + [int(x) for x in failed.get(key, [])]
        tics = ", ".join(f'"{human(x)}" {x}' for x in sorted(set(xs)))
        x0, y0 = rows[0][0], rows[0][1]
        g += [f"set title '{title}'", "set logscale xy", f"set xlabel '{xlabel}'",
              f"set xtics ({tics})", f"set xrange [{min(xs) / 1.4}:{max(xs) * 1.4}]",
              "set key bottom right"]
        ys = [v for r in rows for v in r[1:] if v]
        if ys:  # the data decide the range; the reference line is clipped
            g.append(f"set yrange [{min(ys) / 2}:{max(ys) * 2}]")
        if failed.get(key):
            g.append(f"set label 2 'failed: {', '.join(human(int(x)) for x in failed[key])}' "
                     "at graph 0.98, graph 0.95 right tc rgb 'red'")
        g += [f"plot '{p}' using 1:2 with linespoints lw 2 pt 7 title 'shadow maps', "
              f"'' using 1:3 with linespoints lw 2 pt 5 title 'lighting', "
              f"'' using 1:4 with linespoints lw 2 pt 9 title 'total', "
              f"{y0} * (x / {x0}) ** {power} with lines dt 2 lc rgb 'gray' "
              f"title 'shadow maps, {reflabel} from the first point'",
              "unset xlabel", "unset label 2", "set xtics autofreq", "set autoscale"]
    g.append("unset multiplot")
    script = os.path.join(work, "plot.gp")
    with open(script, "w") as f:
        f.write("\n".join(g) + "\n")
    p = subprocess.run([gnuplot, script], capture_output=True, text=True)
    if p.returncode != 0:
        print("gnuplot failed:\n" + p.stderr, file=sys.stderr)
        return False
    return True


def load_csv(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["scenario"] != "strategies":
                r["parameter"] = int(r["parameter"])
            for key in ("run", "triangles", "lights", "resolution", "width", "height"):
                r[key] = int(r[key])
            rows.append(r)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin")
    ap.add_argument("--gen")
    ap.add_argument("--out", required=True)
    ap.add_argument("--runs", type=int)
    ap.add_argument("--warmup", type=int, default=1,
                    help="untimed renders of the first configuration before each scenario's rounds")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--range", default="auto")
    ap.add_argument("--lights-per-point", type=int, default=8)
    ap.add_argument("--timeout", type=int, default=900)
    ap.add_argument("--keep-scenes", action="store_true")
    ap.add_argument("--report-only", action="store_true",
                    help="redo summary.md and the plot from the --out folder's shadows.csv")
    ap.add_argument("--command", help="the command line, for the report")
    ap.add_argument("scenarios", nargs="*")
    a = ap.parse_args()
    info_path = os.path.join(a.out, "run-info.json")
    rows = None
    if a.report_only:
        rows = load_csv(os.path.join(a.out, "shadows.csv"))
        if not rows:
            sys.exit("bench-shadows: no runs in " + os.path.join(a.out, "shadows.csv"))
        info = json.load(open(info_path)) if os.path.exists(info_path) else {}
        a.__dict__.update({k: v for k, v in info.get("args", {}).items()})
        a.runs = max(r["run"] for r in rows)
        a.width, a.height = rows[0]["width"], rows[0]["height"]
        a.has_shadow_pass = any(r["strategy"] != "default" for r in rows)
        found = []
        for r in rows:
            if r["scenario"] not in found:
                found.append(r["scenario"])
        a.scenarios = found
    scenarios = []
    for s in a.scenarios or SCENARIOS:
        s = ALIASES.get(s, s)
        if s not in SCENARIOS:
            sys.exit(f"bench-shadows: unknown scenario {s!r} (one of {', '.join(SCENARIOS)} or 1-4)")
        if s not in scenarios:
            scenarios.append(s)
    if not a.report_only:
        a.runs = a.runs or (1 if a.quick else 5)
        a.width, a.height = (640, 360) if a.quick else (1280, 720)
        help_text = subprocess.run([a.bin, "render", "--help"], capture_output=True, text=True)
        a.has_shadow_pass = "--shadow-pass" in help_text.stdout + help_text.stderr
        if "strategies" in scenarios and not a.has_shadow_pass:
            print("note: this omnishadow has no --shadow-pass option yet; scenario (1) measures "
                  "its default shadow pass only", flush=True)
    configs = plan(a.quick, [s for s in SCENARIOS if s in scenarios], a.has_shadow_pass)

    bench = Bench(a, rows)
    start = time.monotonic()
    try:
        if a.report_only:
            machine, minutes = info.get("machine", []), info.get("minutes", 0.0)
            a.command = info.get("command", a.command)
        else:
            first = next(iter(configs.values()))[0]
            machine = machine_lines(a.bin, bench.scene(dict(first, triangles=10000, lights=1,
                                                            resolution=64))[0])
            for s, cs in configs.items():
                bench.run_scenario(s, cs)
            bench.csv_file.close()
            minutes = (time.monotonic() - start) / 60
            with open(info_path, "w") as f:
                json.dump({"machine": machine, "minutes": minutes, "command": a.command,
                           "args": {k: getattr(a, k) for k in
                                    ("quick", "seed", "range", "lights_per_point")}}, f, indent=2)
        lines, data = bench.report(configs)
        header = ["## Results", "", *[f"- {l}" for l in machine],
                  f"- Command: `{a.command}`" if a.command else "",
                  f"- {len(bench.rows)} renders in {minutes:.1f} min; CSV: {bench.csv_path}", ""]
        text = "\n".join([l for l in header if l != ""] + [""] + lines) + "\n"
        print("\n" + text)
        with open(os.path.join(a.out, "summary.md"), "w") as f:
            f.write(text)
        png = os.path.join(a.out, "bench-shadows.png")
        title = (f"omnishadow shadow benchmarks{' (--quick)' if a.quick else ''}, "
                 f"{a.width}x{a.height}, {a.runs} run(s)")
        m = re.search(r"\| ([^|]+?) \|", " ".join(machine))
        if m:
            title += ", " + m.group(1)
        if plot(data, png, bench.work, a.quick, title.replace("'", "")):
            print(f"plot: {png}")
    finally:
        if a.keep_scenes and not a.report_only:
            print(f"scenes kept in {bench.work}")
        else:
            shutil.rmtree(bench.work, ignore_errors=True)


if __name__ == "__main__":
    main()
