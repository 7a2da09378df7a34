#!/usr/bin/env python3
"""No-tuning shadow evaluation (issue 18): every model staged on a floor, seeded random light
rigs of every type and every filter, default shadow settings, rates from `omnishadow verify`.

For each model and rig, one `omnishadow verify --json` run checks every placement (`--types`)
times every filter at once (48 lights): a point, a spot and a sun light around and above the
model, a point and a spot light below its centre in front of the camera (the floor stays below
them), a point and a sun light behind it at a grazing angle (rim lights) and a point light
straight above, each repeated once per filter with every other shadow setting at its default. The summary gives, per light type and filter, the
distribution over (model, rig) of the interior agreement and false-shadow / false-light rates:
worst, 1st percentile (the 99th for the false rates: the bad tail) and median.

    scripts/no_tuning_eval.py --build-dir build --rigs 2 --width 192 --height 144 \\
        --out /tmp/eval [--models Duck,Suzanne] [--seed 1]

Writes <out>/results.jsonl (one line per light per run), <out>/summary.md, and the staged
scenes under <out>/scenes/. Only standard-library Python.
"""

import argparse
import base64
import json
import math
import os
import random
import shutil
import struct
import subprocess
import sys

FILTERS = ["hard", "pcf", "pcf-disk", "poisson", "pcss", "vsm"]
# The first three are placed around and above the model; the others (drawn after them, so the
# first three stay the same for a seed) light it from below its centre in front of the camera,
# from behind it at a grazing angle (rim lights), and from straight above.
TYPES = ["point", "spot", "directional", "point_low", "spot_low", "point_rim", "directional_rim",
         "point_top"]
BAR_AGREEMENT, BAR_ERROR = 0.999, 0.0005
SKIP_VARIANTS = ("glTF-Draco", "glTF-Quantized", "glTF-Embedded")


def find_models(roots):
    """One file per model folder: the plain glTF, else the binary, else the first file found."""
    models = []
    for root in roots:
        for name in sorted(os.listdir(root)):
            folder = os.path.join(root, name)
            if not os.path.isdir(folder) or name == "LICENSES":
                continue
            found = []
            for dirpath, dirnames, filenames in os.walk(folder):
                dirnames.sort()
                if any(v in dirpath for v in SKIP_VARIANTS):
                    continue
                for f in sorted(filenames):
                    if f.endswith((".gltf", ".glb")) and "meshopt" not in f and "quantized" not in f:
                        found.append(os.path.join(dirpath, f))
            if not found:
                continue
            plain = [f for f in found if os.sep + "glTF" + os.sep in f]
            found = plain or found
            label = os.path.basename(root.rstrip("/")).replace("scenes-", "") + "/" + name
            models.append((label, found[0]))
    return models


def read_gltf(path):
    """(json, binary chunk or None)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"glTF":
        return json.loads(data.decode("utf-8")), None
    offset, doc, binary = 12, None, None
    while offset + 8 <= len(data):
        length, kind = struct.unpack_from("<II", data, offset)
        chunk = data[offset + 8 : offset + 8 + length]
        if kind == 0x4E4F534A:
            doc = json.loads(chunk.decode("utf-8"))
        elif kind == 0x004E4942:
            binary = chunk
        offset += 8 + length
    return doc, binary


def stage(model_path, bounds, out_dir):
    """Copies the model's folder and writes staged.gltf: the model plus a floor quad under it,
    four times the model's width. Returns the staged file."""
    os.makedirs(out_dir, exist_ok=True)
    source_dir = os.path.dirname(model_path)
    copy = os.path.join(out_dir, "model")
    if not os.path.exists(copy):
        shutil.copytree(source_dir, copy)
    doc, binary = read_gltf(model_path)
    for b in doc.get("buffers", []):
        if "uri" in b and not b["uri"].startswith("data:"):
            b["uri"] = "model/" + b["uri"]
    for im in doc.get("images", []):
        if "uri" in im and not im["uri"].startswith("data:"):
            im["uri"] = "model/" + im["uri"]
    if binary is not None:
        with open(os.path.join(copy, "glb-binary.bin"), "wb") as f:
            f.write(binary[:doc["buffers"][0]["byteLength"]])  # without the chunk's padding
        doc["buffers"][0]["uri"] = "model/glb-binary.bin"

    lo, hi = bounds["min"], bounds["max"]
    cx, cz = (lo[0] + hi[0]) / 2, (lo[2] + hi[2]) / 2
    half = 2.0 * max(hi[0] - lo[0], hi[2] - lo[2], hi[1] - lo[1])
    y = lo[1]
    positions = [(cx - half, y, cz - half), (cx - half, y, cz + half), (cx + half, y, cz + half),
                 (cx + half, y, cz - half)]
    normals = [(0.0, 1.0, 0.0)] * 4
    indices = [0, 1, 2, 0, 2, 3]
    blob = b"".join(struct.pack("<3f", *p) for p in positions)
    blob += b"".join(struct.pack("<3f", *n) for n in normals)
    blob += struct.pack("<6H", *indices) + b"\0\0"
    buffer = len(doc.setdefault("buffers", []))
    doc["buffers"].append({"byteLength": len(blob),
                           "uri": "data:application/octet-stream;base64," +
                                  base64.b64encode(blob).decode("ascii")})
    views = doc.setdefault("bufferViews", [])
    first_view = len(views)
    views += [{"buffer": buffer, "byteOffset": 0, "byteLength": 48},
              {"buffer": buffer, "byteOffset": 48, "byteLength": 48},
              {"buffer": buffer, "byteOffset": 96, "byteLength": 12}]
    accessors = doc.setdefault("accessors", [])
    first_accessor = len(accessors)
    accessors += [
        {"bufferView": first_view, "componentType": 5126, "count": 4, "type": "VEC3",
         "min": [cx - half, y, cz - half], "max": [cx + half, y, cz + half]},
        {"bufferView": first_view + 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": first_view + 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]
    materials = doc.setdefault("materials", [])
    materials.append({"name": "eval-floor", "pbrMetallicRoughness": {
        "baseColorFactor": [0.7, 0.7, 0.7, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}})
    meshes = doc.setdefault("meshes", [])
    meshes.append({"name": "eval-floor", "primitives": [{
        "attributes": {"POSITION": first_accessor, "NORMAL": first_accessor + 1},
        "indices": first_accessor + 2, "material": len(materials) - 1}]})
    nodes = doc.setdefault("nodes", [])
    nodes.append({"name": "eval-floor", "mesh": len(meshes) - 1})
    scenes = doc.setdefault("scenes", [{"nodes": []}])
    scene = doc.get("scene", 0)
    scenes[scene].setdefault("nodes", []).append(len(nodes) - 1)
    staged = os.path.join(out_dir, "staged.gltf")
    with open(staged, "w") as f:
        json.dump(doc, f)
    return staged


def rig(rng, bounds, more):
    """One random light of each placement and a camera. `rng` places the first three (around
    and above the model) and the camera, `more` the others, so that adding placements keeps the
    first three rigs of a seed what they were."""
    lo, hi = bounds["min"], bounds["max"]
    center = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = 0.5 * math.dist(lo, hi)

    def around(distance_lo, distance_hi, elevation_lo, elevation_hi):
        azimuth = rng.uniform(0, 2 * math.pi)
        elevation = math.radians(rng.uniform(elevation_lo, elevation_hi))
        d = radius * rng.uniform(distance_lo, distance_hi)
        return [center[0] + d * math.cos(elevation) * math.cos(azimuth),
                max(center[1] + d * math.sin(elevation), lo[1] + 0.05 * radius),
                center[2] + d * math.cos(elevation) * math.sin(azimuth)]

    def towards(a, b):
        v = [y - x for x, y in zip(a, b)]
        n = math.sqrt(sum(c * c for c in v))
        return [c / n for c in v]

    point = around(1.3, 4.0, 5, 85)
    spot = around(1.5, 4.0, 10, 85)
    spot_distance = math.dist(spot, center)
    cone = min(math.atan(1.6 * radius / spot_distance), math.radians(80))
    aim = [c + rng.uniform(-0.3, 0.3) * radius for c in center]
    sun = towards(around(2.0, 2.0, 10, 85), center)
    eye = around(2.6, 3.2, 15, 60)
    eye_azimuth = math.atan2(eye[2] - center[2], eye[0] - center[0])
    floor = lo[1] + 0.05 * radius

    def placed(azimuth_offset, spread, distance_lo, distance_hi, height_lo, height_hi):
        """A point at an azimuth relative to the camera's, at a height between two fractions
        of the way from just above the floor (0) to the model's centre (1), never below the
        floor, so the floor stays a receiver and the model is lit from below its centre."""
        azimuth = eye_azimuth + azimuth_offset + math.radians(more.uniform(-spread, spread))
        d = radius * more.uniform(distance_lo, distance_hi)
        y = floor + (center[1] - floor) * more.uniform(height_lo, height_hi)
        return [center[0] + d * math.cos(azimuth), y, center[2] + d * math.sin(azimuth)]

    point_low = placed(0.0, 50, 1.3, 3.0, 0.0, 0.8)
    spot_low = placed(0.0, 50, 1.5, 3.5, 0.0, 0.8)
    spot_low_distance = math.dist(spot_low, center)
    spot_low_cone = min(math.atan(1.6 * radius / spot_low_distance), math.radians(80))
    point_rim = placed(math.pi, 60, 1.5, 3.5, 0.3, 1.6)
    rim_azimuth = eye_azimuth + math.pi + math.radians(more.uniform(-60, 60))
    rim_elevation = math.radians(more.uniform(2, 15))
    sun_rim = [-math.cos(rim_elevation) * math.cos(rim_azimuth), -math.sin(rim_elevation),
               -math.cos(rim_elevation) * math.sin(rim_azimuth)]
    top_azimuth = more.uniform(0, 2 * math.pi)
    top_elevation = math.radians(more.uniform(75, 90))
    top_distance = radius * more.uniform(1.2, 2.5)
    point_top = [center[0] + top_distance * math.cos(top_elevation) * math.cos(top_azimuth),
                 center[1] + top_distance * math.sin(top_elevation),
                 center[2] + top_distance * math.cos(top_elevation) * math.sin(top_azimuth)]
    spot = {"type": "spot", "position": spot, "direction": towards(spot, aim),
            "outerConeAngle": cone, "innerConeAngle": 0.8 * cone}
    return {
        "point": {"type": "point", "position": point},
        "spot": spot,
        "directional": {"type": "directional", "direction": sun},
        "point_low": {"type": "point", "position": point_low},
        "spot_low": {"type": "spot", "position": spot_low, "direction": towards(spot_low, center),
                     "outerConeAngle": spot_low_cone, "innerConeAngle": 0.8 * spot_low_cone},
        "point_rim": {"type": "point", "position": point_rim},
        "directional_rim": {"type": "directional", "direction": sun_rim},
        "point_top": {"type": "point", "position": point_top},
        "camera": {"eye": eye, "target": center},
    }


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def percentile(values, p):
    v = sorted(values)
    if not v:
        return float("nan")
    k = (len(v) - 1) * p / 100.0
    f, c = math.floor(k), math.ceil(k)
    return v[f] if f == c else v[f] + (v[c] - v[f]) * (k - f)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--build-dir", default="build")
    ap.add_argument("--roots", default="../shared/scenes-khronos,../shared/scenes-thirdparty")
    ap.add_argument("--models", default="", help="comma-separated model names (default: all)")
    ap.add_argument("--rigs", type=int, default=2, help="light rigs per model")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--height", type=int, default=144)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--types", default=",".join(TYPES),
                    help="comma-separated light placements to check (default: all of "
                         + ", ".join(TYPES) + ")")
    ap.add_argument("--extra", default="", help="extra shadow settings for every light, JSON "
                    "(e.g. '{\"normalBias\": 2}'), to measure alternatives; default: none")
    ap.add_argument("--out", required=True)
    ap.add_argument("--summarize-only", action="store_true",
                    help="only rebuild <out>/summary.md from <out>/results.jsonl")
    args = ap.parse_args()
    if args.summarize_only:
        rows = [json.loads(line) for line in open(os.path.join(args.out, "results.jsonl"))]
        labels = sorted({r["model"] for r in rows})
        lines = summarize(rows, args, [(m, None) for m in labels], [])
        with open(os.path.join(args.out, "summary.md"), "w") as f:
            f.write("\n".join(lines) + "\n")
        print("\n".join(lines))
        return

    binary = os.path.join(args.build_dir, "omnishadow")
    roots = [r for r in args.roots.split(",") if r and os.path.isdir(r)]
    models = find_models(roots)
    if args.models:
        wanted = set(args.models.split(","))
        models = [m for m in models if m[0].split("/")[1] in wanted or m[0] in wanted]
    extra = json.loads(args.extra) if args.extra else {}
    types = [t for t in args.types.split(",") if t]
    unknown = [t for t in types if t not in TYPES]
    if unknown:
        sys.exit(f"--types: unknown placement {', '.join(unknown)} (known: {', '.join(TYPES)})")
    os.makedirs(args.out, exist_ok=True)
    results_path = os.path.join(args.out, "results.jsonl")
    failures = []
    with open(results_path, "w") as results:
        for label, path in models:
            info = run([binary, "info", path, "--json"])
            if info.returncode != 0:
                failures.append(f"{label}: info failed: {info.stderr.strip()}")
                continue
            bounds = json.loads(info.stdout)["bounds"]
            if not bounds or bounds.get("min") is None:
                failures.append(f"{label}: empty scene")
                continue
            staged = stage(path, bounds, os.path.join(args.out, "scenes", label.replace("/", "_")))
            rng = random.Random(f"{args.seed}:{label}")
            more = random.Random(f"{args.seed}:{label}:more placements")
            for r in range(args.rigs):
                lights_rig = rig(rng, bounds, more)
                lights = []
                for t in types:
                    for f in FILTERS:
                        shadow = {"filter": f}
                        shadow.update(extra)
                        light = dict(lights_rig[t])
                        light.update({"name": f"{t}-{f}", "intensity": 1.0, "shadow": shadow})
                        lights.append(light)
                lights_path = os.path.join(os.path.dirname(staged), f"rig{r}.lights.json")
                with open(lights_path, "w") as lf:
                    json.dump({"lights": lights}, lf)
                cam = lights_rig["camera"]
                cmd = [binary, "verify", staged, "-l", lights_path, "--no-gltf-lights",
                       "--width", str(args.width), "--height", str(args.height),
                       "--eye", ",".join(f"{c:.9g}" for c in cam["eye"]),
                       "--target", ",".join(f"{c:.9g}" for c in cam["target"]),
                       "--fov", "45", "--threads", str(args.threads), "--json",
                       "--error-image", os.path.join(os.path.dirname(staged), f"rig{r}-errors.png")]
                v = run(cmd)
                if v.returncode not in (0, 1):
                    failures.append(f"{label} rig {r}: exit {v.returncode}: {v.stderr.strip()}")
                    continue
                report = json.loads(v.stdout)
                for light in report["lights"]:
                    t, f = light["name"].split("-", 1)
                    results.write(json.dumps({"model": label, "rig": r, "type": t, "filter": f,
                                              "interior": light["interior"],
                                              "edge": light["edge"]}) + "\n")
                results.flush()  # a run stopped early still leaves every finished rig
                print(f"{label} rig {r}: done", file=sys.stderr, flush=True)

    rows = [json.loads(line) for line in open(results_path)]
    lines = summarize(rows, args, models, failures)
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def summarize(rows, args, models, failures):
    lines = [f"Command: `scripts/no_tuning_eval.py --rigs {args.rigs} --seed {args.seed} "
             f"--width {args.width} --height {args.height}"
             + (f" --models {args.models}" if args.models else "")
             + (f" --types {args.types}" if args.types != ",".join(TYPES) else "")
             + (f" --extra '{args.extra}'" if args.extra else "") + "`",
             f"Models ({len(models)}): " + ", ".join(m[0] for m in models), ""]
    lines.append("| light | filter | runs | interior agreement: worst / 1st pct / median | "
                 "false shadow: worst / 99th pct / median | false light: worst / 99th pct / median"
                 " | runs over the bar |")
    lines.append("|---|---|---|---|---|---|---|")
    misses = []
    for t in TYPES:
        for f in FILTERS:
            sel = [r for r in rows if r["type"] == t and r["filter"] == f
                   and r["interior"]["evaluated"]]
            if not sel:
                continue
            agree = [r["interior"]["agreementRate"] for r in sel]
            fs = [r["interior"]["falseShadowRate"] for r in sel]
            fl = [r["interior"]["falseLightRate"] for r in sel]
            bad = [r for r in sel if r["interior"]["agreementRate"] < BAR_AGREEMENT
                   or r["interior"]["falseShadowRate"] > BAR_ERROR
                   or r["interior"]["falseLightRate"] > BAR_ERROR]
            misses += bad
            pct = lambda x: f"{100 * x:.3f}%"
            lines.append(f"| {t} | {f} | {len(sel)} | {pct(min(agree))} / "
                         f"{pct(percentile(agree, 1))} / {pct(percentile(agree, 50))} | "
                         f"{pct(max(fs))} / {pct(percentile(fs, 99))} / {pct(percentile(fs, 50))} | "
                         f"{pct(max(fl))} / {pct(percentile(fl, 99))} / {pct(percentile(fl, 50))} | "
                         f"{len(bad)} |")
    lines += ["", f"Runs over the bar ({len(misses)}):", ""]
    for r in sorted(misses, key=lambda r: (r["model"], r["rig"], r["type"], r["filter"])):
        i = r["interior"]
        lines.append(f"- {r['model']} rig {r['rig']} {r['type']} {r['filter']}: agreement "
                     f"{100 * i['agreementRate']:.3f}%, false shadow {i['falseShadow']} "
                     f"({100 * i['falseShadowRate']:.3f}%), false light {i['falseLight']} "
                     f"({100 * i['falseLightRate']:.3f}%) of {i['evaluated']}")
    if failures:
        lines += ["", "Not evaluated:", ""] + [f"- {x}" for x in failures]
    return lines


if __name__ == "__main__":
    main()
