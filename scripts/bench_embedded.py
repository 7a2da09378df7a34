#!/usr/bin/env python3
"""Loading glTF-Embedded files: base64 data: URIs against the same model with its files.

The Khronos samples ship every model as glTF-Embedded too (buffers and images as base64 data:
URIs inside the JSON). This writes that twin of each .gltf model that has files of its own (in
a temporary folder), then times, in interleaved rounds, an `info` process and the `load` stage
of `render --stats` at 320x240 on the twin, with the binary under test and an optional
baseline, and on the model with its files as the reference. It also checks that each
binary's picture of the twin is byte-identical to its picture of the model with its files.
Prints a markdown table of medians.

Usage: scripts/bench_embedded.py [--bin FILE] [--baseline FILE] [--rounds N] [MODEL.gltf ...]
With no models: the .gltf models with files of their own under ../shared/scenes-thirdparty
and ../shared/scenes-khronos/*/glTF."""
import argparse, base64, glob, json, os, re, statistics, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")


def embedded_twin(path, out_dir):
    """Writes the model with every buffer and image file as a data: URI; returns its path, or
    None when the model has no file of its own."""
    doc = json.load(open(path))
    folder = os.path.dirname(path)
    changed = False
    for key in ("buffers", "images"):
        for item in doc.get(key, []):
            uri = item.get("uri")
            if not uri or uri.startswith("data:"):
                continue
            raw = open(os.path.join(folder, uri), "rb").read()
            if key == "buffers":
                mime = "application/octet-stream"
            else:
                mime = "image/png" if raw.startswith(b"\x89PNG") else "image/jpeg"
            item["uri"] = f"data:{mime};base64," + base64.b64encode(raw).decode()
            changed = True
    if not changed:
        return None
    stem = os.path.splitext(os.path.basename(path))[0]
    out = os.path.join(out_dir, f"{stem}.gltf")
    json.dump(doc, open(out, "w"))
    return out


def default_models():
    found = sorted(glob.glob(os.path.join(SHARED, "scenes-thirdparty", "*", "*.gltf")) +
                   glob.glob(os.path.join(SHARED, "scenes-khronos", "*", "glTF", "*.gltf")))
    return found


def run(cmd):
    start = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    wall = (time.perf_counter() - start) * 1000
    if p.returncode != 0:
        sys.exit(f"bench_embedded: {' '.join(cmd)} failed:\n{p.stderr[-800:]}")
    return wall, p.stderr


def load_ms(binary, scene, png):
    _, err = run([binary, "render", scene, "-o", png, "--width", "320", "--height", "240",
                  "--stats"])
    m = re.search(r"^load\s+([\d.]+)$", err, re.M)
    return float(m.group(1)) if m else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "omnishadow"))
    ap.add_argument("--baseline", help="another omnishadow, measured in the same rounds")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("models", nargs="*")
    a = ap.parse_args()
    binaries = {"new": a.bin}
    if a.baseline:
        binaries["baseline"] = a.baseline
    tmp = tempfile.mkdtemp(prefix="bench-embedded.")
    models = []
    for path in a.models or default_models():
        twin = embedded_twin(path, tmp)
        if twin:
            models.append((os.path.splitext(os.path.basename(path))[0], path, twin))
    if not models:
        sys.exit("bench_embedded: no .gltf model with files of its own")
    # The pictures first: each binary's picture of the twin is its picture of the files.
    for name, files, twin in models:
        for who, binary in binaries.items():
            pngs = [os.path.join(tmp, f"{name}.{who}.{kind}.png") for kind in ("files", "twin")]
            load_ms(binary, files, pngs[0])
            load_ms(binary, twin, pngs[1])
            if open(pngs[0], "rb").read() != open(pngs[1], "rb").read():
                sys.exit(f"bench_embedded: {who}: {name}: the twin's picture differs")
    times = {}
    for r in range(a.rounds):
        for name, files, twin in models:
            jobs = [("files", "new", files)] + [("twin", who, twin) for who in binaries]
            # Alternate the order each round, so that no binary always runs right after another.
            for kind, who, scene in (jobs if r % 2 == 0 else jobs[::-1]):
                binary = binaries[who]
                wall, _ = run([binary, "info", scene])
                times.setdefault((name, kind, who, "info"), []).append(wall)
                times.setdefault((name, kind, who, "load"), []).append(
                    load_ms(binary, scene, os.path.join(tmp, "frame.png")))
        print(f"# round {r + 1} of {a.rounds} done", file=sys.stderr, flush=True)
    med = lambda *key: statistics.median(times[key])  # noqa: E731
    head = "| model | JSON MB | with its files: info / load ms | embedded, new: info / load ms |"
    rule = "|---|---:|---:|---:|"
    if a.baseline:
        head += " embedded, baseline: info / load ms | load new / baseline |"
        rule += "---:|---:|"
    print(head)
    print(rule)
    for name, files, twin in models:
        size = os.path.getsize(twin) / 1e6
        row = (f"| {name} | {size:.1f} | {med(name, 'files', 'new', 'info'):.0f} / "
               f"{med(name, 'files', 'new', 'load'):.1f} | {med(name, 'twin', 'new', 'info'):.0f} / "
               f"{med(name, 'twin', 'new', 'load'):.1f} |")
        if a.baseline:
            row += (f" {med(name, 'twin', 'baseline', 'info'):.0f} / "
                    f"{med(name, 'twin', 'baseline', 'load'):.1f} | "
                    f"{med(name, 'twin', 'new', 'load') / med(name, 'twin', 'baseline', 'load'):.2f} |")
        print(row)
    print(f"\n{a.rounds} interleaved rounds, medians; `info`: the whole process; load: the `load` "
          "stage of `render --stats` at 320x240. Pictures of each twin byte-identical to the "
          "model's with its files, for each binary.")


if __name__ == "__main__":
    main()
