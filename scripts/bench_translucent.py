#!/usr/bin/env python3
"""What translucent shadows cost (README, "Translucent shadows"). Standard library only. Not a
test: numbers only.

Writes a scene (a floor, 16 colored glass panes with BLEND and KHR_materials_transmission, four
opaque boxes) and two lights files (a sun, a point light and a spot light, 1024-texel maps, one
file with "translucentShadows": false), renders both with `omnishadow render --stats` in
interleaved rounds (on, off, on, off, ... so the noise of a shared machine hits both alike) and
prints the median "shadow maps", "lighting" and "total" stage times and their ratios.

    scripts/bench_translucent.py --omnishadow build/omnishadow --runs 7
    scripts/bench_translucent.py --omnishadow build/omnishadow --runs 5 --aov
    scripts/bench_translucent.py --omnishadow build/omnishadow --scene S.glb --lights L.json
"""
import argparse
import base64
import json
import os
import statistics
import struct
import subprocess
import sys
import tempfile


def panes_scene(path):
    positions, indices, primitives = [], [], []

    def quad(y, x0, z0, x1, z1):
        b = len(positions)
        positions.extend([(x0, y, z0), (x1, y, z0), (x0, y, z1), (x1, y, z1)])
        indices.extend([b, b + 2, b + 1, b + 1, b + 2, b + 3])

    def box(cx, cy, cz, h):
        b = len(positions)
        for dx in (-h, h):
            for dy in (-h, h):
                for dz in (-h, h):
                    positions.append((cx + dx, cy + dy, cz + dz))
        for a, b1, c, d in [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4),
                            (1, 5, 7, 3)]:
            indices.extend([b + a, b + b1, b + c, b + a, b + c, b + d])

    def primitive(material, make):
        start = len(indices)
        make()
        primitives.append((start, len(indices) - start, material))

    primitive(0, lambda: quad(0.0, -4, -4, 4, 4))
    for i in range(4):
        for j in range(4):
            x, z = -3 + i * 1.6, -3 + j * 1.6
            primitive(1 + (i + j) % 3,
                      lambda x=x, z=z, i=i: quad(1.0 + 0.2 * i, x, z, x + 1.2, z + 1.2))
    for x, z in [(-2, -2), (2, 2), (-2, 2), (2, -2)]:
        primitive(0, lambda x=x, z=z: box(x, 0.3, z, 0.3))
    position_bytes = b"".join(struct.pack("<3f", *p) for p in positions)
    index_bytes = b"".join(struct.pack("<I", i) for i in indices)
    data = position_bytes + index_bytes
    accessors = [{"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
                  "min": [min(p[k] for p in positions) for k in range(3)],
                  "max": [max(p[k] for p in positions) for k in range(3)]}]
    mesh = []
    for start, count, material in primitives:
        accessors.append({"bufferView": 1, "byteOffset": start * 4, "componentType": 5125,
                          "count": count, "type": "SCALAR"})
        mesh.append({"attributes": {"POSITION": 0}, "indices": len(accessors) - 1,
                     "material": material})

    def glass(color):
        return {"pbrMetallicRoughness": {"baseColorFactor": color}, "alphaMode": "BLEND",
                "doubleSided": True,
                "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.8}}}

    gltf = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_transmission"],
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(position_bytes)},
                        {"buffer": 0, "byteOffset": len(position_bytes),
                         "byteLength": len(index_bytes)}],
        "accessors": accessors,
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1]}},
                      glass([1, 0.3, 0.2, 0.5]), glass([0.2, 1, 0.3, 0.5]),
                      glass([0.3, 0.4, 1, 0.5])],
        "meshes": [{"primitives": mesh}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}],
        "scene": 0}
    with open(path, "w") as out:
        json.dump(gltf, out)


def lights_files(folder, lights):
    with open(lights) as f:
        setup = json.load(f)
    paths = {}
    for mode, translucent in (("on", True), ("off", False)):
        for light in setup["lights"]:
            light["translucentShadows"] = translucent
        paths[mode] = os.path.join(folder, "lights-" + mode + ".json")
        with open(paths[mode], "w") as out:
            json.dump(setup, out)
    return paths


DEFAULT_LIGHTS = {"lights": [
    {"name": "sun", "type": "directional", "direction": [0.3, -1, -0.4], "intensity": 3},
    {"name": "lamp", "type": "point", "position": [0.5, 4, 0.3], "intensity": 30},
    {"name": "spot", "type": "spot", "position": [-1, 5, 1], "direction": [0.2, -1, -0.2],
     "outerConeAngle": 0.9, "intensity": 40}]}


def stages(output):
    found = {}
    for line in output.splitlines():
        for stage in ("shadow maps", "lighting", "total"):
            if line.startswith(stage + " "):
                found[stage] = float(line[len(stage):].split()[0])
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--omnishadow", required=True)
    parser.add_argument("--scene", help="default: the generated glass panes")
    parser.add_argument("--lights", help="default: a sun, a point and a spot light")
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--aov", action="store_true", help="also write the AOVs")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        scene = args.scene
        if not scene:
            scene = os.path.join(folder, "panes.gltf")
            panes_scene(scene)
        lights = args.lights
        if not lights:
            lights = os.path.join(folder, "lights.json")
            with open(lights, "w") as out:
                json.dump(DEFAULT_LIGHTS, out)
        files = lights_files(folder, lights)
        times = {"on": [], "off": []}
        for _ in range(args.runs):
            for mode in ("on", "off"):
                command = [args.omnishadow, "render", scene, "-l", files[mode], "--stats",
                           "--width", str(args.width), "--height", str(args.height),
                           "-o", os.path.join(folder, mode + ".png")]
                if not args.scene:
                    command += ["--eye", "0,7,7", "--target", "0,0,0"]
                if args.aov:
                    command += ["--aov", os.path.join(folder, mode + ".exr")]
                run = subprocess.run(command, capture_output=True, text=True)
                if run.returncode != 0:
                    sys.exit(run.stderr)
                times[mode].append(stages(run.stdout + run.stderr))
        print("command: " + " ".join(sys.argv))
        medians = {}
        for mode in ("on", "off"):
            medians[mode] = {s: statistics.median(t[s] for t in times[mode])
                             for s in ("shadow maps", "lighting", "total")}
            print("translucentShadows %-5s median of %d: shadow maps %7.1f ms, lighting %7.1f ms,"
                  " total %7.1f ms" % ("true" if mode == "on" else "false", args.runs,
                                       medians[mode]["shadow maps"], medians[mode]["lighting"],
                                       medians[mode]["total"]))
        print("ratio true/false: shadow maps %.2f, lighting %.2f, total %.2f" % tuple(
            medians["on"][s] / medians["off"][s] for s in ("shadow maps", "lighting", "total")))


if __name__ == "__main__":
    main()
