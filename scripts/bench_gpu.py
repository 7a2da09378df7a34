#!/usr/bin/env python3
"""The frame-speed tables on a machine with a GPU (scripts/bench-gpu.sh).

Needs nothing but the binaries and a scene folder, so that it runs on a bare machine that
cannot build (a lent GPU). Sections, each written to OUT/gpu.md as soon as it is done:
  info     the EGL device, GL renderer and driver; `--version` time; a 64x64 Box render
  peers    the peers' scenes (compare.py's lights, pcf, 1024^2 cube maps) at 1280x720: process
           wall time and first frame with a cold and a warm shader cache, the steady frame of
           `render --repeat`, and how far the GPU's image is from llvmpipe's (`omnishadow diff`)
  passes   the 250k-triangle bench room, 4 point lights at 1024^2: each --shadow-pass, every
           round listed, against `geometry`
  lights   256 shadowed point lights on 1M triangles (the many-lights frame)
  prepass  the beauty's depth pre-pass forced on and off against auto (off on GPUs), on the
           many-lights frame and three peers' scenes: steady lighting, and whether on and off
           draw the same picture (an NVIDIA driver once failed the pre-pass's depth test)
  verify   `omnishadow verify` on three scenes: the device's shadows against exact ray casting
  occlusion  ambient occlusion's cost: four peers' scenes with an ambient term, steady frames
           without and with `"ambient_occlusion": true`, and the occlusion layer against llvmpipe's
  batch    generated small scenes through `omnishadow batch`: scenes per second by workers
Rounds are interleaved (A, B, C, A, B, C, ...) so that drift hits every configuration alike."""
import argparse, glob, json, os, re, shutil, statistics, subprocess, sys, tempfile, time

PEERS = ["box", "cornell", "sundial", "whackamole", "test_room"]
PASSES = ["six", "geometry", "instanced", "batched", "auto"]


def stages(text):
    """--stats lines ("shadow maps  12.3", "steady lighting  4.5") summed by name."""
    out = {}
    for line in text.splitlines():
        m = re.match(r"^(\w[\w :]*?)\s+([\d.]+)$", line.strip())
        if m:
            out[m.group(1)] = out.get(m.group(1), 0.0) + float(m.group(2))
    return out


class Bench:
    def __init__(self, a):
        self.a = a
        self.tmp = tempfile.mkdtemp(prefix="bench-gpu.")
        self.md = []
        self.warm_cache = os.path.join(self.tmp, "cache-warm")
        os.makedirs(self.warm_cache)

    def env(self, cache):
        e = dict(os.environ)
        # NVIDIA's and Mesa's on-disk shader caches, pointed at one folder per run kind.
        e.update(__GL_SHADER_DISK_CACHE="1", __GL_SHADER_DISK_CACHE_PATH=cache,
                 __GL_SHADER_DISK_CACHE_SKIP_CLEANUP="1", MESA_SHADER_CACHE_DIR=cache)
        return e

    def run(self, args, cache=None, binary=None):
        cache = cache or self.warm_cache
        timeout = self.a.timeout
        t0 = time.perf_counter()
        p = subprocess.run([binary or self.a.bin] + args, capture_output=True, text=True,
                           timeout=timeout, env=self.env(cache))
        wall = (time.perf_counter() - t0) * 1000
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(args[:3])}: exit {p.returncode}: {p.stderr[-600:]}")
        st = stages(p.stderr)
        st["wall"] = wall
        st["first"] = st.get("shadow maps", 0) + st.get("lighting", 0) + st.get("readback", 0)
        st["stderr"] = p.stderr
        return st

    def cold_cache(self):
        d = tempfile.mkdtemp(dir=self.tmp, prefix="cache-cold.")
        return d

    def write(self, title, lines):
        self.md += [f"## {title}", ""] + lines + [""]
        os.makedirs(self.a.out, exist_ok=True)
        with open(os.path.join(self.a.out, "gpu.md"), "w") as f:
            f.write("\n".join(self.md) + "\n")
        print("\n".join([f"## {title}", ""] + lines + [""]), flush=True)

    # --- sections -------------------------------------------------------------------------
    def info(self):
        lines = []
        for cmd in (["nvidia-smi", "--query-gpu=name,driver_version,memory.total",
                     "--format=csv,noheader"], ["nproc"]):
            try:
                lines.append(f"- `{cmd[0]}`: " + subprocess.run(
                    cmd, capture_output=True, text=True, timeout=30).stdout.strip())
            except (OSError, subprocess.SubprocessError) as e:
                lines.append(f"- `{cmd[0]}`: {e}")
        dev = subprocess.run([self.a.bin, "devices"], capture_output=True, text=True)
        lines += ["- `omnishadow devices`:", "", "```", dev.stdout.strip() + dev.stderr.strip(),
                  "```", ""]
        box = self.scene("box")
        st = self.run(["render", box[0], "-l", box[1], "-o", f"{self.tmp}/v.png", "-v",
                       "--width", "64", "--height", "64", "--no-gltf-lights"])
        gl = [l for l in st["stderr"].splitlines() if l.startswith("omnishadow: ")]
        lines += ["- `render -v`:", "", "```"] + gl[:2] + ["```", ""]
        version, small = [], []
        for _ in range(self.a.rounds * 2):
            t0 = time.perf_counter()
            subprocess.run([self.a.bin, "--version"], capture_output=True, env=self.env(self.warm_cache))
            version.append((time.perf_counter() - t0) * 1000)
            small.append(self.run(["render", box[0], "-l", box[1], "-o", f"{self.tmp}/s.png",
                                   "--width", "64", "--height", "64", "--no-gltf-lights"])["wall"])
        lines += [f"- `omnishadow --version`: median {statistics.median(version):.1f} ms "
                  f"({len(version)} runs)",
                  f"- 64x64 render of Box (a process, warm shader cache): median "
                  f"{statistics.median(small):.1f} ms, all {fmt_list(small)}"]
        self.write("Machine", lines)

    def hardware_device(self):
        """The index of the first hardware EGL device in `omnishadow devices`, else 0."""
        text = subprocess.run([self.a.bin, "devices"], capture_output=True, text=True).stdout
        for line in text.splitlines():
            f = line.split()
            if f and f[0].isdigit() and f[-1] == "hardware":
                return f[0]
        return "0"

    def scene(self, name):
        for ext in (".glb", ".gltf"):
            p = os.path.join(self.a.scenes, name + ext)
            if os.path.exists(p):
                return p, os.path.join(self.a.scenes, name + ".lights.json")
        raise FileNotFoundError(f"{self.a.scenes}: no scene {name}")

    def peers(self):
        w, h = 1280, 720
        res = {n: {"cold": [], "warm": [], "steady": [], "baseline": []} for n in PEERS}
        for r in range(self.a.rounds):
            for n in PEERS:
                scene, lights = self.scene(n)
                base = ["render", scene, "-l", lights, "--width", str(w), "--height", str(h),
                        "--no-gltf-lights", "--stats"]
                out = f"{self.tmp}/{n}.png"
                res[n]["cold"].append(self.run(base + ["-o", out], cache=self.cold_cache()))
                res[n]["warm"].append(self.run(base + ["-o", out]))
                res[n]["steady"].append(self.run(base + ["-o", out, "--repeat", str(self.a.repeat)]))
                if self.a.baseline_bin:
                    res[n]["baseline"].append(self.run(
                        base + ["-o", f"{self.tmp}/{n}.baseline.png", "--repeat", str(self.a.repeat)],
                        binary=self.a.baseline_bin))
                if r == 0:
                    shutil.copy(out, os.path.join(self.a.out, f"{n}.gpu.png"))
                    if self.a.baseline_bin:
                        res[n]["same"] = (open(out, "rb").read() ==
                                          open(f"{self.tmp}/{n}.baseline.png", "rb").read())
        lines = ["Medians of %d interleaved rounds (ms). Cold: an empty shader cache folder; "
                 "first frame = shadow maps + lighting + readback of the one frame; steady = "
                 "median frame of `render --repeat %d` (lights moved, every shadow map redrawn)."
                 % (self.a.rounds, self.a.repeat), "",
                 "| scene | process cold | process warm | first frame cold | first frame warm "
                 "| shaders cold | shaders warm | steady frame | steady shadow maps | steady lighting "
                 "| steady readback |", "|---|" + "---:|" * 10]
        for n in PEERS:
            c, wm, s = res[n]["cold"], res[n]["warm"], res[n]["steady"]
            med = lambda rows, k: statistics.median(x.get(k, float("nan")) for x in rows)
            lines.append(f"| {n} | {med(c, 'wall'):.0f} | {med(wm, 'wall'):.0f} | "
                         f"{med(c, 'first'):.1f} | {med(wm, 'first'):.1f} | "
                         f"{med(c, 'shaders'):.1f} | {med(wm, 'shaders'):.1f} | "
                         f"{med(s, 'steady frame'):.2f} | {med(s, 'steady shadow maps'):.2f} | "
                         f"{med(s, 'steady lighting'):.2f} | {med(s, 'steady readback'):.2f} |")
        if self.a.baseline_bin:
            lines += ["", f"The baseline (`{os.path.basename(self.a.baseline_bin)}`) in the same rounds, "
                      "steady (medians, ms): this binary / the baseline; and whether the two "
                      "PNGs are the same bytes:", "",
                      "| scene | steady frame | steady shadow maps | steady lighting | steady readback "
                      "| PNG |", "|---|---:|---:|---:|---:|---|"]
            for n in PEERS:
                cell = lambda k: (f"{statistics.median(x.get(k, float('nan')) for x in res[n]['steady']):.2f} / "
                                  f"{statistics.median(x.get(k, float('nan')) for x in res[n]['baseline']):.2f}")
                same = "byte-identical" if res[n].get("same") else "DIFFER"
                lines.append(f"| {n} | {cell('steady frame')} | {cell('steady shadow maps')} | "
                             f"{cell('steady lighting')} | {cell('steady readback')} | {same} |")
        stage_names = [k for k in res["test_room"]["warm"][0] if k not in ("wall", "first", "stderr")]
        lines += ["", "Every stage of the warm first frame (medians, ms):", "",
                  "| scene | " + " | ".join(stage_names) + " |",
                  "|---|" + "---:|" * len(stage_names)]
        for n in PEERS:
            lines.append(f"| {n} | " + " | ".join(
                f"{statistics.median(x.get(k, 0) for x in res[n]['warm']):.1f}" for k in stage_names) + " |")
        if self.a.reference:
            lines += diff_table_head("The GPU's image against llvmpipe's (`omnishadow diff`, "
                                     "8-bit RGB as 0..1):")
            for n in PEERS:
                ref = os.path.join(self.a.reference, f"{n}.png")
                if not os.path.exists(ref):
                    continue
                lines.append(diff_row(self.a.bin, n, ref, os.path.join(self.a.out, f"{n}.gpu.png")))
        self.write("Peers' scenes, 1280x720, pcf, 1024^2 cube maps", lines)

    def passes(self):
        room = os.path.join(self.tmp, "room.gltf")
        subprocess.run([self.a.shadow_gen, room, "--triangles", "250000", "--lights", "4",
                        "--resolution", "1024"], check=True, capture_output=True)
        rows = {p: [] for p in PASSES}
        for _ in range(self.a.rounds):
            for p in PASSES:
                # Each stage finished, so that the shadow maps' time holds their GPU work.
                rows[p].append(self.run(["render", room, "-o", f"{self.tmp}/room-{p}.png", "--stats",
                                         "--shadow-pass", p, "--repeat", str(self.a.repeat),
                                         "--finish-each-stage", "on"]))
        geo_first = [x["shadow maps"] for x in rows["geometry"]]
        geo_steady = [x["steady shadow maps"] for x in rows["geometry"]]
        lines = ["250k triangles, 4 point lights, 1024^2 cube maps, 1280x720; `shadow maps` stage "
                 "in ms, each round listed (first frame | steady median of `--repeat %d`)."
                 % self.a.repeat, "",
                 "| pass | first frame, rounds | steady, rounds | steady median | x geometry "
                 "(every round) |", "|---|---|---|---:|---|"]
        for p in PASSES:
            first = [x["shadow maps"] for x in rows[p]]
            steady = [x["steady shadow maps"] for x in rows[p]]
            ratio = [s / g for s, g in zip(steady, geo_steady)]
            lines.append(f"| {p} | {fmt_list(first)} | {fmt_list(steady)} | "
                         f"{statistics.median(steady):.2f} | {fmt_list(ratio, 2)} |")
        same = all(open(f"{self.tmp}/room-{p}.png", "rb").read() ==
                   open(f"{self.tmp}/room-six.png", "rb").read() for p in PASSES)
        lines += ["", f"Beauty images of all passes byte-identical: {'yes' if same else 'NO'}"]
        self.write("Shadow passes (bench room)", lines)

    def lights(self):
        tris = self.a.many_triangles
        lines = [f"{tris / 1e6:g}M triangles, 256 shadowed point lights (generator's ranges), steady frame of "
                 "`render --repeat %d` (ms, medians of %d rounds; every shadow map redrawn each "
                 "frame)." % (self.a.repeat, self.a.rounds), "",
                 "Each stage's wait: the part of it spent in glFinish, waiting for the GPU. Without "
                 "`--finish-each-stage on` (the default on GPUs) the upload and the shadow maps "
                 "end without one, so their stage is the CPU's submission and the lighting's "
                 "wait holds what is left of the maps' GPU work.", "",
                 "| cube map | image | --shadow-pass | steady frame | shadow maps | its wait | "
                 "lighting | its wait | readback | first frame |",
                 "|---|---|---|---:|---:|---:|---:|---:|---:|---:|"]
        for i, res in enumerate(map(int, self.a.many_resolutions.split(","))):
            scene, mem = self.many_scene(res)
            # Both image sizes at the first cube map size only: the larger maps change the
            # shadow stage, not the lighting.
            for w, h in ((1280, 720), (1920, 1080))[:2 if i == 0 else 1]:
                # The default pass against the others, round by round.
                rows = {p: [] for p in self.a.many_passes.split(",")}
                # The default pass with each stage finished: the shadow maps' own GPU work, and
                # what the overlap of the lighting's CPU work with it is worth.
                rows["auto, each stage finished"] = []
                if self.a.baseline_bin:  # the baseline binary's default pass, same rounds
                    rows["auto, baseline"] = []
                for _ in range(self.a.rounds):
                    for p in rows:
                        finish = ["--finish-each-stage", "on"] if "finished" in p else []
                        rows[p].append(self.run(["render", scene, "-o", f"{self.tmp}/many.png",
                                                 "--stats", "--width", str(w), "--height", str(h),
                                                 "--max-memory", f"{mem:.0f}", "--shadow-pass",
                                                 p.split(",")[0], "--repeat", str(self.a.repeat)]
                                                + finish,
                                                binary=self.a.baseline_bin if "baseline" in p else None))
                for p, runs in rows.items():
                    med = lambda k: statistics.median(x.get(k, float("nan")) for x in runs)
                    lines.append(f"| {res}^2 | {w}x{h} | {p} | {med('steady frame'):.2f} | "
                                 f"{med('steady shadow maps'):.2f} | "
                                 f"{med('steady GPU wait: shadow maps'):.2f} | "
                                 f"{med('steady lighting'):.2f} | "
                                 f"{med('steady GPU wait: lighting'):.2f} | "
                                 f"{med('steady readback'):.2f} | {med('first'):.1f} |")
        self.write(f"256 shadowed point lights on {tris / 1e6:g}M triangles", lines)

    def many_scene(self, res):
        """The 256-light scene at cube maps of res^2, made once, and the --max-memory it needs."""
        scene = os.path.join(self.tmp, f"many{res}.gltf")
        if not os.path.exists(scene):
            subprocess.run([self.a.shadow_gen, scene, "--triangles", str(self.a.many_triangles),
                            "--lights", "256", "--resolution", str(res)], check=True,
                           capture_output=True)
        return scene, max(4096, 256 * 6 * res * res * 4 * 1.5 / 2**20)

    def prepass(self):
        res = int(self.a.many_resolutions.split(",")[0])
        many, mem = self.many_scene(res)
        cases = [(f"256 lights, {res}^2", many, ["--max-memory", f"{mem:.0f}"], w, h)
                 for w, h in ((1280, 720), (1920, 1080))]
        for n in ("cornell", "whackamole", "test_room"):
            scene, lights = self.scene(n)
            cases.append((n, scene, ["-l", lights, "--no-gltf-lights"], 1280, 720))
        modes = ("auto", "on", "off")
        rows = {(c[0], c[3], m): [] for c in cases for m in modes}
        for _ in range(self.a.rounds):
            for case, (name, scene, extra, w, h) in enumerate(cases):
                for m in modes:
                    out = f"{self.tmp}/prepass-{case}-{m}.png"
                    rows[(name, w, m)].append(self.run(
                        ["render", scene, *extra, "-o", out, "--stats", "--width", str(w),
                         "--height", str(h), "--depth-prepass", m, "--repeat", str(self.a.repeat)]))
                    rows[(name, w, m)][-1]["png"] = out
        lines = ["Steady `lighting` of `render --repeat %d` in ms (medians of %d rounds), "
                 "`--depth-prepass` auto, on and off; on / auto round by round; and on against "
                 "off (`omnishadow diff` of the last round's PNGs)." % (self.a.repeat, self.a.rounds),
                 "", "| scene | image | auto | on | off | on / auto (every round) | on against off |",
                 "|---|---|---:|---:|---:|---|---|"]
        for name, _, _, w, h in cases:
            lit = {m: [x.get("steady lighting", float("nan")) for x in rows[(name, w, m)]]
                   for m in modes}
            on_png, off_png = rows[(name, w, "on")][-1]["png"], rows[(name, w, "off")][-1]["png"]
            same = open(on_png, "rb").read() == open(off_png, "rb").read()
            versus = "byte-identical" if same else (
                "differ (max abs, mean abs, PSNR, pixels): " +
                diff_row(self.a.bin, "", on_png, off_png).strip("| ").replace(" | ", ", "))
            lines.append(f"| {name} | {w}x{h} | {statistics.median(lit['auto']):.2f} | "
                         f"{statistics.median(lit['on']):.2f} | {statistics.median(lit['off']):.2f} | "
                         f"{fmt_list([o / a for o, a in zip(lit['on'], lit['auto'])], 2)} | "
                         f"{versus} |")
        self.write("The depth pre-pass: auto, on and off", lines)

    def verify(self):
        """The GPU's shadow maps against exact ray casting: the rates per light."""
        lines = ["`omnishadow verify` (the renderer's shadow maps on this device against Embree):", "",
                 "| scene | light | interior agreement | interior false shadow | interior false light |",
                 "|---|---|---:|---|---|"]
        for n in ("cornell", "sundial", "test_room"):
            scene, lights = self.scene(n)
            p = subprocess.run([self.a.bin, "verify", scene, "-l", lights, "--no-gltf-lights"],
                               capture_output=True, text=True, env=self.env(self.warm_cache))
            light = "?"
            for line in p.stdout.splitlines() + p.stderr.splitlines():
                m = re.match(r'^light "(.*?)"', line)
                if m:
                    light = m.group(1)
                f = line.split()
                if f[:1] == ["interior"] and len(f) >= 7:
                    lines.append(f"| {n} | {light} | {f[2]} | {' '.join(f[3:5])} | {' '.join(f[5:7])} |")
        self.write("Shadows against the exact reference", lines)

    def occlusion(self):
        """What screen-space ambient occlusion costs on this device, and how far its estimate is
        from the same estimate on llvmpipe (the reference folder's NAME.occlusion.png)."""
        names = ("cornell", "sundial", "whackamole", "test_room")
        variants = {}
        for n in names:
            scene, lights = self.scene(n)
            variants[n] = (scene, occlusion_lights(lights, self.tmp, n, False),
                           occlusion_lights(lights, self.tmp, n, True))
        rows = {(n, on): [] for n in names for on in (False, True)}
        for _ in range(self.a.rounds):
            for n in names:
                scene, off, on = variants[n]
                for flag, lights in ((False, off), (True, on)):
                    rows[(n, flag)].append(self.run(
                        ["render", scene, "-l", lights, "--no-gltf-lights", "--stats",
                         "--width", "1280", "--height", "720", "-o", f"{self.tmp}/ao.png",
                         "--repeat", str(self.a.repeat)]))
        lines = ["The peers' scenes with an ambient of 0.3 added to their lights, without and with "
                 "`\"ambient_occlusion\": true` (1280x720; ms, medians of %d interleaved rounds of "
                 "`render --repeat %d`)." % (self.a.rounds, self.a.repeat), "",
                 "| scene | steady frame without | with | steady lighting without | with | "
                 "first frame without | with |", "|---|---:|---:|---:|---:|---:|---:|"]
        for n in names:
            med = lambda on, k: statistics.median(x.get(k, float("nan")) for x in rows[(n, on)])
            lines.append(f"| {n} | {med(False, 'steady frame'):.2f} | {med(True, 'steady frame'):.2f} | "
                         f"{med(False, 'steady lighting'):.2f} | {med(True, 'steady lighting'):.2f} | "
                         f"{med(False, 'first'):.1f} | {med(True, 'first'):.1f} |")
        if self.a.reference:
            lines += diff_table_head("The `occlusion` debug view on this device against "
                                     "llvmpipe's (`omnishadow diff`, 8-bit as 0..1):")
            for n in names:
                ref = os.path.join(self.a.reference, f"{n}.occlusion.png")
                if not os.path.exists(ref):
                    continue
                scene, _, on = variants[n]
                out = os.path.join(self.a.out, f"{n}.occlusion.gpu.png")
                self.run(["render", scene, "-l", on, "--no-gltf-lights", "--width", "1280",
                          "--height", "720", "--debug-view", "occlusion", "-o", out])
                lines.append(diff_row(self.a.bin, n, ref, out))
        self.write("Ambient occlusion", lines)

    def batch(self):
        self.device = self.hardware_device()
        scenes = os.path.join(self.tmp, "batch-scenes")
        subprocess.run([self.a.batch_gen, scenes, str(self.a.batch_scenes), "1"], check=True,
                       capture_output=True)
        n = len(glob.glob(os.path.join(scenes, "*.glb")))
        configs = []
        for size in ("320x240", "1280x720"):
            for workers in (1, 2, 4, 8):
                configs.append((size, workers))
        times = {c: [] for c in configs}
        for _ in range(self.a.rounds):
            for size, workers in configs:
                out = os.path.join(self.tmp, "batch-out")
                shutil.rmtree(out, ignore_errors=True)
                w, h = size.split("x")
                gpus = ",".join([self.device] * workers)
                t = self.run(["batch", scenes, "--out", out, "--width", w, "--height", h, "--quiet",
                              "--gpus", gpus])["wall"]
                times[(size, workers)].append(t)
        lines = [f"{n} generated scenes (two 256^2 shadowed point lights each), one `omnishadow "
                 f"batch` process; `--gpus 0,0,...` runs that many workers on the GPU. Wall time "
                 f"of the whole process, medians of {self.a.rounds} rounds.", "",
                 "| image | workers | seconds | scenes per second |", "|---|---:|---:|---:|"]
        for size, workers in configs:
            s = statistics.median(times[(size, workers)]) / 1000
            lines.append(f"| {size} | {workers} | {s:.2f} | {n / s:.0f} |")
        self.write("Batch throughput", lines)


def occlusion_lights(lights, folder, name, on):
    """NAME's lights with an ambient term of 0.3, and ambient occlusion when on."""
    with open(lights) as f:
        data = json.load(f)
    data["ambient"] = [0.3, 0.3, 0.3]
    data["ambient_occlusion"] = on
    path = os.path.join(folder, f"{name}.ao-{'on' if on else 'off'}.lights.json")
    with open(path, "w") as f:
        json.dump(data, f)
    return path


def diff_table_head(title):
    """The lines before diff_row()'s rows: a blank line, the title and the table's head."""
    return ["", title, "", "| scene | max abs | mean abs | PSNR dB | pixels that differ |",
            "|---|---:|---:|---:|---:|"]


def diff_row(binary, name, a, b):
    """One table row of `omnishadow diff A B`'s "all" line (max, mean, RMSE, PSNR, count, share)."""
    p = subprocess.run([binary, "diff", a, b], capture_output=True, text=True)
    for line in (p.stdout + p.stderr).splitlines():
        f = line.split()
        if f[:1] == ["all"] and len(f) >= 7:
            return f"| {name} | {float(f[1]):.4f} | {float(f[2]):.2e} | {f[4]} | {f[5]} {f[6]} |"
    return f"| {name} | ? | ? | ? | {(p.stdout + p.stderr).strip()[-80:]} |"


def fmt_list(xs, digits=1):
    return " ".join(f"{x:.{digits}f}" for x in xs)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", required=True, help="omnishadow")
    ap.add_argument("--shadow-gen", required=True, help="make_shadow_bench_scene")
    ap.add_argument("--batch-gen", required=True, help="make_bench_scenes")
    ap.add_argument("--scenes", required=True,
                    help="folder with box, cornell, sundial, whackamole, test_room (.glb/.gltf) "
                         "and NAME.lights.json beside each")
    ap.add_argument("--reference", help="folder with NAME.png rendered elsewhere (llvmpipe)")
    ap.add_argument("--baseline-bin", help="another omnishadow, timed in the same rounds (peers' "
                    "steady frames, the many-lights frame's default pass)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--ld-library-path", help="the libraries of the binaries under test, given to "
                    "them alone: this Python may need its own machine's versions of the same ones")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--timeout", type=float, default=600,
                    help="seconds one omnishadow process may take before its section is given up")
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--batch-scenes", type=int, default=200)
    ap.add_argument("--many-triangles", type=int, default=1000000)
    ap.add_argument("--many-resolutions", default="512,1024", help="cube map sizes of the 256 lights")
    ap.add_argument("--many-passes", default="auto,instanced,batched",
                    help="--shadow-pass values timed on the many-lights frame")
    ap.add_argument("--sections", default="info,peers,passes,verify,lights,prepass,occlusion,batch")
    a = ap.parse_args()
    if a.ld_library_path:  # read by the loader of each child process, not by this one
        old = os.environ.get("LD_LIBRARY_PATH")
        os.environ["LD_LIBRARY_PATH"] = a.ld_library_path + (":" + old if old else "")
    os.makedirs(a.out, exist_ok=True)
    b = Bench(a)
    failed = False
    for s in a.sections.split(","):
        t0 = time.time()
        try:
            getattr(b, s)()
        except Exception as e:  # one section's failure must not cost the others' numbers
            failed = True
            b.write(f"{s}: failed", [f"    {type(e).__name__}: {e}"])
        print(f"[{s}: {time.time() - t0:.0f} s]", file=sys.stderr, flush=True)
    shutil.rmtree(b.tmp, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
