#!/usr/bin/env python3
"""Shadow documentation: the filter gallery and the measured error rates and filter costs.

Driven by scripts/make-shadow-gallery.sh and scripts/measure-shadow-quality.sh (which build the
binaries first); see those for usage. Every light used is defined here, once, so that the
pictures in docs/images/shadows/ and the numbers in docs/shadow-quality.md describe the same
lights.
"""
import argparse
import datetime
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

FILTERS = ["hard", "pcf", "pcf-disk", "poisson", "pcss", "vsm"]
TYPES = ["point", "spot", "directional"]
TYPE_LABEL = {"point": "point", "spot": "spot", "directional": "directional (sun)"}

# The light's size for pcss (and for the exact reference, which then casts 64 rays to a disk):
# world units for point and spot lights, the sun's angular radius in radians.
PCSS_RADIUS = {"point": 0.15, "spot": 0.15, "directional": 0.02}

AMBIENT = [0.02, 0.02, 0.02]

# The demo scene (scenes/demo/room.gltf): one light of each type, every shadow setting at its
# default except the filter (and `near`, as in the demo's own lights, and `cascades` for the
# sun). The point light is the demo's "warm" light; the spot light hangs near the right wall and
# aims at the floor objects; the sun comes in through the room's open front at a slant
# (about 66 degrees from the floor's normal) with two cascades.
DEMO_LIGHTS = {
    "point": {"name": "point", "type": "point", "position": [-0.8, 3.0, 0.6],
              "color": [1.0, 0.85, 0.65], "intensity": 18, "shadow": {"near": 0.08}},
    "spot": {"name": "spot", "type": "spot", "position": [2.6, 3.6, 1.4],
             "direction": [-2.8, -3.6, -1.9], "innerConeAngle": 0.55, "outerConeAngle": 0.7,
             "color": [1.0, 0.92, 0.8], "intensity": 40, "shadow": {"near": 0.08}},
    "directional": {"name": "sun", "type": "directional", "direction": [-0.5, -0.45, -1.0],
                    "color": [1.0, 0.95, 0.85], "intensity": 5, "shadow": {"cascades": 2}},
}

# Focused scenes (scenes/builder/make_shadow_quality_scenes.cpp), one light of each type per
# render, all with the same filter and default bias.
# (a) a plane lit at 80 degrees from its normal: the sun's direction, and the point and spot
# lights 10 m away at 1.763 m height (tan 10 degrees), aimed at the plane's center.
GRAZING_LIGHTS = [
    {"name": "point", "type": "point", "position": [-10, 1.7633, 0], "intensity": 60},
    {"name": "spot", "type": "spot", "position": [-10, 1.7633, 0], "direction": [10, -1.7633, 0],
     "outerConeAngle": 0.6, "intensity": 60},
    {"name": "sun", "type": "directional", "direction": [0.98481, -0.17365, 0], "intensity": 3},
]
# (b) a 2 cm board standing on a floor, lit from its front (-z) side.
THIN_LIGHTS = [
    {"name": "point", "type": "point", "position": [-0.4, 1.6, -1.4], "intensity": 6},
    {"name": "spot", "type": "spot", "position": [0.5, 2.0, -1.6], "direction": [-0.5, -2.0, 2.0],
     "outerConeAngle": 0.6, "intensity": 8},
    {"name": "sun", "type": "directional", "direction": [0.25, -0.75, 0.6], "intensity": 2},
]

# The focused scenes' light names and their types.
NAME_TYPE = {"point": "point", "spot": "spot", "sun": "directional"}

# Settings varied one at a time from the defaults (filter pcf) on the focused scenes, for the
# guidance in the README's "Shadow settings": (scene key, settings).
VARIATIONS = [
    ("grazing", {"slopeBias": 0, "minBias": 0, "normalBias": 0}),
    ("grazing", {"normalBias": 0}),
    ("grazing", {"slopeBias": 0, "minBias": 0}),
    ("grazing", {"depthFormat": "24"}),
    ("thin-foot", {"bias": 0.05}),
    ("thin-foot", {"normalBias": 4}),
    ("thin-foot", {"cullFace": "back"}),
    ("thin-foot", {"cullFace": "front"}),
    ("thin-foot", {"depthFormat": "24"}),
]

# Issue 3's bar, on evaluated interior points.
BAR_AGREEMENT = 0.999
BAR_FALSE = 0.0005


def with_filter(light, filt, light_type):
    light = json.loads(json.dumps(light))
    shadow = light.setdefault("shadow", {})
    shadow["filter"] = filt
    if filt == "pcss":
        shadow["radius"] = PCSS_RADIUS[light_type]
    return light


def write_lights(path, lights):
    with open(path, "w") as f:
        json.dump({"ambient": AMBIENT, "lights": lights}, f, indent=2)
        f.write("\n")


def run(cmd, **kw):
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    if result.returncode != 0:
        sys.stderr.write(result.stdout + result.stderr)
        raise SystemExit(f"shadow-docs: failed ({result.returncode}): {' '.join(cmd)}")
    return result


def rel(path):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = os.path.abspath(path)
    return os.path.relpath(path, root) if path.startswith(root + os.sep) else path


# ---------------------------------------------------------------------------------- gallery

LABEL_FONTS = ["/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf",  # fonts-dejavu-core
               "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"]


def label_font(tmp):
    """A font oiiotool can draw labels with, or None (then the sheets have no labels)."""
    for font in LABEL_FONTS:
        if not os.path.exists(font):
            continue
        probe = os.path.join(tmp, "label-probe.png")
        result = subprocess.run(["oiiotool", "--create", "64x16", "3",
                                 f"--text:x=2:y=12:size=12:font={font}", "x", "-o", probe],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if result.returncode == 0 and os.path.exists(probe):
            return font
    return None


def gallery(args):
    os.makedirs(args.out, exist_ok=True)
    scene = os.path.join(args.root, "scenes", "demo", "room.gltf")
    with tempfile.TemporaryDirectory(prefix="shadow-gallery.") as tmp:
        font = label_font(tmp) if shutil.which("oiiotool") else None
        for light_type in TYPES:
            pictures = []
            for filt in FILTERS:
                lights = os.path.join(tmp, f"{light_type}-{filt}.lights.json")
                write_lights(lights, [with_filter(DEMO_LIGHTS[light_type], filt, light_type)])
                picture = os.path.join(args.out, f"{light_type}-{filt}.png")
                run([args.bin, "render", scene, "-l", lights, "--width", str(args.width),
                     "--height", str(args.height), "-o", picture])
                pictures.append((filt, picture))
                print(f"wrote {rel(picture)}  ({os.path.getsize(picture) // 1024} KB)")
            if not shutil.which("oiiotool"):
                print("shadow-gallery: oiiotool not found (openimageio-tools); no contact sheets",
                      file=sys.stderr)
                continue
            # Contact sheet: the six filters, 3x2, each cropped at 1:1 to the lower middle
            # three quarters (the floor objects and the lattice), labelled when a font works.
            # --nosoftwareattrib keeps oiiotool's command line (temporary paths) out of the
            # files, so that a rerun writes the same bytes.
            crop_w, crop_h = args.width * 3 // 4, args.height * 3 // 4
            crop = f"{crop_w}x{crop_h}+{args.width // 24}+{args.height - crop_h}"
            tiles = []
            for filt, picture in pictures:
                tile = os.path.join(tmp, f"tile-{light_type}-{filt}.png")
                cmd = ["oiiotool", "--nosoftwareattrib", picture, "--cut", crop]
                if font:
                    cmd += [f"--text:x=7:y=21:size=15:color=0,0,0:font={font}", filt,
                            f"--text:x=6:y=20:size=15:color=1,1,1:font={font}", filt]
                run(cmd + ["-d", "uint8", "-o", tile])
                tiles.append(tile)
            sheet = os.path.join(args.out, f"{light_type}-filters.png")
            run(["oiiotool", "--nosoftwareattrib"] + tiles +
                ["--mosaic:pad=2", "3x2", "--attrib", "png:compressionLevel", "9", "-d", "uint8",
                 "-o", sheet])
            print(f"wrote {rel(sheet)}  ({os.path.getsize(sheet) // 1024} KB)")


# ---------------------------------------------------------------------------------- measure

def verify(args, scene, lights_path, tag, extra=()):
    error_image = os.path.join(args.work, f"{tag}-errors.png")
    result = run([args.bin, "verify", scene, "-l", lights_path, "--width", str(args.width),
                  "--height", str(args.height), "--json", "--error-image", error_image,
                  *extra])
    report = json.loads(result.stdout)
    for light in report["lights"]:
        light["errorImage"] = error_image
    return report["lights"]


STAGE_LINE = re.compile(r"^(shadow maps|lighting)\s+([0-9.]+)\s*$")


def render_stats(args, scene, lights_path):
    result = run([args.bin, "render", scene, "-l", lights_path, "--width", str(args.width),
                  "--height", str(args.height), "--stats",
                  "-o", os.path.join(args.work, "timing.png")])
    stages = {}
    for line in result.stderr.splitlines():
        match = STAGE_LINE.match(line.strip())
        if match:
            stages[match.group(1)] = float(match.group(2))
    if "lighting" not in stages or "shadow maps" not in stages:
        raise SystemExit("shadow-docs: no 'lighting'/'shadow maps' stage in --stats output:\n" +
                         result.stderr)
    return stages


def pct(x):
    return "-" if x is None else f"{100.0 * x:.4f}%"


def count_pct(group, key):
    rate = group[key + "Rate"]
    return "-" if rate is None else f"{group[key]} ({100.0 * rate:.4f}%)"


def meets_bar(light):
    i = light["interior"]
    if not i["evaluated"]:
        return True
    return (i["agreementRate"] >= BAR_AGREEMENT and i["falseShadowRate"] <= BAR_FALSE and
            i["falseLightRate"] <= BAR_FALSE)


def skipped_text(skipped):
    short = {"background": "bg", "outOfRange": "range", "outsideCone": "cone",
             "facingAway": "away", "grazing": "grazing", "beyondShadowFar": "far", "unlit": "unlit"}
    parts = [f"{short[k]} {v}" for k, v in skipped.items() if v]
    return ", ".join(parts) if parts else "0"


def rates_table(rows, with_cost):
    head = ["light", "filter", "interior points", "interior agreement",
            "interior false shadow", "interior false light", "edge points", "edge agreement",
            "edge false shadow", "edge false light", "skipped"]
    if with_cost:
        head += ["shadow maps ms", "lighting ms"]
    head.append("bar")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in rows:
        light = row["light"]
        i, e = light["interior"], light["edge"]
        cells = [row["label"], light["filter"], str(i["evaluated"]), pct(i["agreementRate"]),
                 count_pct(i, "falseShadow"), count_pct(i, "falseLight"), str(e["evaluated"]),
                 pct(e["agreementRate"]), count_pct(e, "falseShadow"), count_pct(e, "falseLight"),
                 skipped_text(light["skipped"])]
        if with_cost:
            cells += [f"{row['shadow maps']:.1f}", f"{row['lighting']:.1f}"]
        cells.append("ok" if meets_bar(light) else "**MISS**")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def variations_table(rows):
    scene_label = {"grazing": "grazing plane", "thin-foot": "thin caster, foot"}
    lines = ["| scene | settings (else default, filter pcf) | light | interior false shadow | "
             "interior false light | edge false shadow | edge false light | bar |",
             "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        i, e = row["light"]["interior"], row["light"]["edge"]
        settings = ", ".join(f"`{k}` {json.dumps(v)}" for k, v in row["settings"].items())
        lines.append("| " + " | ".join([
            scene_label[row["scene"]], settings, row["label"], count_pct(i, "falseShadow"),
            count_pct(i, "falseLight"), count_pct(e, "falseShadow"), count_pct(e, "falseLight"),
            "ok" if meets_bar(row["light"]) else "**MISS**"]) + " |")
    return "\n".join(lines)


def cost_table(cost):
    head = ["filter"] + [f"{TYPE_LABEL[t]}: shadow maps / lighting ms" for t in TYPES]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for filt in ["unshadowed"] + FILTERS:
        cells = [f"`{filt}`" if filt != "unshadowed" else "no shadow (`\"shadow\": false`)"]
        for light_type in TYPES:
            c = cost[(light_type, filt)]
            cells.append(f"{c['shadow maps']:.0f} / {c['lighting']:.0f}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def machine_description(args):
    renderer = "unknown GL renderer"
    result = subprocess.run([args.bin, "render", "-v", "--width", "16", "--height", "9", "-o",
                             os.path.join(args.work, "probe.png")], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    for line in result.stdout.splitlines():
        if "|" in line:
            renderer = line.split(":", 1)[1].strip()
            break
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{os.cpu_count()} cores ({cpu}), GL: {renderer}"


def measure(args):
    os.makedirs(args.work, exist_ok=True)
    scene = os.path.join(args.root, "scenes", "demo", "room.gltf")
    lights_dir = os.path.join(args.work, "lights")
    os.makedirs(lights_dir, exist_ok=True)

    # Demo scene: one verify per light type and filter.
    configs = []
    for light_type in TYPES:
        for filt in FILTERS:
            path = os.path.join(lights_dir, f"demo-{light_type}-{filt}.lights.json")
            write_lights(path, [with_filter(DEMO_LIGHTS[light_type], filt, light_type)])
            configs.append((light_type, filt, path))
    demo_rows = []
    for light_type, filt, path in configs:
        print(f"verify demo {light_type} {filt}", file=sys.stderr)
        (light,) = verify(args, scene, path, f"demo-{light_type}-{filt}")
        demo_rows.append({"label": TYPE_LABEL[light_type], "type": light_type, "light": light})

    # Cost: `render --stats`, rounds interleaved over every configuration (and the same light
    # without shadows, the baseline), medians.
    timed = list(configs)
    for light_type in TYPES:
        path = os.path.join(lights_dir, f"demo-{light_type}-unshadowed.lights.json")
        light = json.loads(json.dumps(DEMO_LIGHTS[light_type]))
        light["shadow"] = False
        write_lights(path, [light])
        timed.append((light_type, "unshadowed", path))
    times = {(t, f): {"lighting": [], "shadow maps": []} for t, f, _ in timed}
    # An untimed round first: llvmpipe compiles each shader variant at its first draw (inside
    # these stages) and Mesa's disk cache keeps it, so every timed run finds a warm cache.
    print("timing: warm-up round", file=sys.stderr)
    for light_type, filt, path in timed:
        render_stats(args, scene, path)
    for round_index in range(args.runs):
        print(f"timing round {round_index + 1}/{args.runs}", file=sys.stderr)
        for light_type, filt, path in timed:
            stages = render_stats(args, scene, path)
            for stage in ("lighting", "shadow maps"):
                times[(light_type, filt)][stage].append(stages[stage])
    cost = {key: {stage: statistics.median(runs) for stage, runs in value.items()}
            for key, value in times.items()}
    for row, (light_type, filt, _) in zip(demo_rows, configs):
        for stage in ("lighting", "shadow maps"):
            row[stage] = cost[(light_type, filt)][stage]
        row["runs"] = times[(light_type, filt)]

    # Focused scenes: three lights (one per type) per render, one render per filter.
    scenes_dir = os.path.join(args.work, "scenes")
    run([args.gen, scenes_dir])
    focused = {"grazing": [], "thin-contact": [], "thin-foot": []}
    for filt in FILTERS:
        for name, lights, scene_file, cameras in (
                ("grazing", GRAZING_LIGHTS, "grazing-plane.glb", [("grazing", None)]),
                ("thin", THIN_LIGHTS, "thin-caster.glb",
                 [("thin-contact", "contact"), ("thin-foot", "foot")])):
            path = os.path.join(lights_dir, f"{name}-{filt}.lights.json")
            write_lights(path, [with_filter(l, filt, NAME_TYPE[l["name"]]) for l in lights])
            for key, camera in cameras:
                print(f"verify {key} {filt}", file=sys.stderr)
                extra = ["--camera", camera] if camera else []
                for light in verify(args, os.path.join(scenes_dir, scene_file), path,
                                    f"{key}-{filt}", extra):
                    focused[key].append({"label": TYPE_LABEL[NAME_TYPE[light["name"]]],
                                         "light": light})
    # Settings varied one at a time, filter pcf.
    variation_rows = []
    for index, (key, settings) in enumerate(VARIATIONS):
        lights = GRAZING_LIGHTS if key == "grazing" else THIN_LIGHTS
        scene_file = "grazing-plane.glb" if key == "grazing" else "thin-caster.glb"
        extra = [] if key == "grazing" else ["--camera", "foot"]
        varied = []
        for light in lights:
            light = with_filter(light, "pcf", NAME_TYPE[light["name"]])
            light["shadow"].update(settings)
            varied.append(light)
        path = os.path.join(lights_dir, f"variation{index}-{key}.lights.json")
        write_lights(path, varied)
        print(f"verify {key} {json.dumps(settings)}", file=sys.stderr)
        for light in verify(args, os.path.join(scenes_dir, scene_file), path,
                            f"variation{index}-{key}", extra):
            variation_rows.append({"scene": key, "settings": settings,
                                   "label": TYPE_LABEL[NAME_TYPE[light["name"]]], "light": light})

    for key in focused:  # by light type, then filter
        focused[key].sort(key=lambda r: (TYPES.index(r["light"]["type"]),
                                         FILTERS.index(r["light"]["filter"])))

    misses = [(name, r) for name, rows in
              [("demo", demo_rows), ("grazing plane", focused["grazing"]),
               ("thin caster (contact view)", focused["thin-contact"]),
               ("thin caster (foot close-up)", focused["thin-foot"])]
              for r in rows if not meets_bar(r["light"])]

    date = datetime.date.today().isoformat()
    doc = f"""# Shadow quality: measured error rates and filter costs

Generated by `{args.command}` on {date}.
Machine: {machine_description(args)}.
Images {args.width}x{args.height}; every shadow setting at its default (README, "Shadow
settings") except the filter, `near` 0.08 for the demo's point and spot lights, `cascades` 2 for
the demo's sun, and the light's `radius` for `pcss` ({PCSS_RADIUS['point']} m for point and spot
lights, {PCSS_RADIUS['directional']} rad for the sun). The lights are defined in
`scripts/shadow_docs.py`; `omnishadow verify` rules at their defaults (skip N.L < 0.05, edge band
3 texels plus the filter's reach, 64 rays per point to a light with a radius).

Rates are fractions of the evaluated points of their group, as `omnishadow verify` reports them
(README, "`omnishadow verify`"). Issue 3's bar, on **interior** points: agreement >= 99.9%, false
shadow <= 0.05%, false light <= 0.05%. Edge points disagree by design (a filtered map draws a
soft edge a few texels wide; pcss draws a penumbra the reference measures as a fraction).

## Demo scene, one light at a time

`scenes/demo/room.gltf`, one light per render: the demo's warm point light, a spot light aimed at
the floor objects, a sun through the open front with 2 cascades. Costs: median over {args.runs}
interleaved runs of `omnishadow render --stats` with that light alone (stages "shadow maps" and
"lighting", milliseconds of wall time, one frame), after an untimed warm-up round: llvmpipe
compiles each shader variant at its first draw, inside these stages, and Mesa's shader cache
(`~/.cache/mesa_shader_cache`) keeps it, so the timed runs do not include compiling (a cold
first run costs 0.2 to 1.8 s more here). Every run is in `results.json` of the work folder.

{rates_table(demo_rows, True)}

The costs again, per filter (median milliseconds of the "shadow maps" and "lighting" stages, one
light, {args.width}x{args.height}, 1024-texel maps; the first row is the same light without
shadows):

{cost_table(cost)}

## Acne: a plane lit at a grazing 80 degrees

A 20 m plane and nothing else, so every shadowed point is acne. The sun's direction is 80 degrees
from the normal; the point and spot lights are 10 m away and 1.76 m high (80 degrees at the
plane's center, more grazing farther away, steeper nearer).

{rates_table(focused["grazing"], False)}

## Leaks: a 2 cm board standing on a floor

A 1.5 m x 1 m board, 2 cm thick, on a 10 cm floor slab, lit from its front; seen from its
shadowed side. "contact" frames the whole board and its shadow; "foot" is a close-up of the
middle of the contact line and the 60 cm of floor behind it (no outer shadow edge in view), so
light seen there is a leak under the board.

### Camera "contact"

{rates_table(focused["thin-contact"], False)}

### Camera "foot"

{rates_table(focused["thin-foot"], False)}

## Settings varied one at a time

The same focused scenes with filter `pcf` and one group of settings changed from the defaults
(the error images are `variation<N>-<scene>-errors.png`). Misses here are expected: they show
what each default is for.

{variations_table(variation_rows)}

## Against the bar (default settings)

"""
    if misses:
        doc += "Combinations missing the bar:\n\n"
        for name, r in misses:
            i = r["light"]["interior"]
            doc += (f"- {name}: {r['label']} `{r['light']['filter']}`: interior agreement "
                    f"{pct(i['agreementRate'])}, false shadow {count_pct(i, 'falseShadow')}, "
                    f"false light {count_pct(i, 'falseLight')} (error image "
                    f"`{rel(r['light']['errorImage'])}`)\n")
    else:
        doc += "Every light type and filter meets the bar on every scene above.\n"
    doc += ("\nError images (`--error-image`: red = false shadow, blue = false light, half "
            f"brightness on edge points) are in `{rel(args.work)}/`.\n")

    print(doc)
    if args.doc:
        os.makedirs(os.path.dirname(os.path.abspath(args.doc)), exist_ok=True)
        with open(args.doc, "w") as f:
            f.write(doc)
        print(f"wrote {rel(args.doc)}", file=sys.stderr)
    with open(os.path.join(args.work, "results.json"), "w") as f:
        json.dump({"demo": demo_rows, **focused, "variations": variation_rows,
                   "timing": [{"type": t, "filter": f, **v} for (t, f), v in times.items()]},
                  f, indent=1)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    sub = parser.add_subparsers(dest="mode", required=True)
    g = sub.add_parser("gallery")
    g.add_argument("--bin", required=True)
    g.add_argument("--out", required=True)
    g.add_argument("--width", type=int, default=480)
    g.add_argument("--height", type=int, default=270)
    m = sub.add_parser("measure")
    m.add_argument("--bin", required=True)
    m.add_argument("--gen", required=True, help="make_shadow_quality_scenes")
    m.add_argument("--work", required=True, help="lights files, scenes, error images")
    m.add_argument("--doc", help="also write the markdown here")
    m.add_argument("--runs", type=int, default=3)
    m.add_argument("--width", type=int, default=640)
    m.add_argument("--height", type=int, default=360)
    m.add_argument("--command", default="scripts/measure-shadow-quality.sh")
    args = parser.parse_args()
    args.root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    gallery(args) if args.mode == "gallery" else measure(args)


if __name__ == "__main__":
    main()
