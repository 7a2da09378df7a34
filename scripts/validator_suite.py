#!/usr/bin/env python3
"""Runs every .gltf/.glb of the glTF-Validator test suite through `omnishadow info` and
`omnishadow render` (small size, per-run timeout) and compares the exit codes with the file's
expected report (<file>.report.json). Run by scripts/validator-suite.sh.

A file is flagged when a run
  - ends by a signal (a crash) or runs past the timeout (a hang),
  - exits with a status other than 0, 1 or 2, or prints more than one line for an error,
  - exits 0 although the expected report lists errors, and printed no warning (a silent
    accept; the renderer may ignore objects it does not use, but then it says nothing wrong
    was drawn, which this script cannot tell: such files are listed for a person to judge).
Exit status: 1 when any crash, hang or malformed error was found, else 0.
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile


def expected_errors(path):
    report = path + ".report.json"
    try:
        with open(report, encoding="utf-8") as f:
            issues = json.load(f)["issues"]
    except (OSError, ValueError, KeyError):
        return None, []
    codes = sorted({m["code"] for m in issues.get("messages", []) if m.get("severity") == 0})
    return issues.get("numErrors", 0), codes


def run(binary, args, timeout, cwd):
    try:
        p = subprocess.run([binary] + args, cwd=cwd, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "hang", ""
    err = p.stderr.decode("utf-8", "replace")
    if p.returncode < 0:
        return "signal %d" % -p.returncode, err
    return p.returncode, err


def check(binary, path, timeout, size):
    errors, codes = expected_errors(path)
    with tempfile.TemporaryDirectory(prefix="omnishadow-validator-") as out:
        info = run(binary, ["info", path], timeout, out)
        render = run(binary, ["render", path, "-o", os.path.join(out, "a.png"), "--width",
                              str(size), "--height", str(size)], timeout, out)
        wrote = os.path.exists(os.path.join(out, "a.png"))
    problems = []
    for name, (status, err) in (("info", info), ("render", render)):
        lines = [l for l in err.splitlines() if l.startswith("omnishadow: ")]
        errors_printed = [l for l in lines if not l.startswith("omnishadow: warning:")]
        if isinstance(status, str):
            problems.append("%s: %s" % (name, status))
        elif status not in (0, 1, 2):
            problems.append("%s: exit %d" % (name, status))
        elif status != 0 and (len(errors_printed) != 1 or len(err.splitlines()) != len(lines)):
            problems.append("%s: exit %d without exactly one error line" % (name, status))
        if name == "render" and status != 0 and wrote:
            problems.append("render: failed but left an image")
    warned = "omnishadow: warning:" in render[1]
    silent = errors and render[0] == 0 and not warned
    return {
        "file": path, "errors": errors, "codes": codes, "info": info[0], "render": render[0],
        "warned": warned, "problems": problems, "silent": bool(silent),
        "message": next((l for l in render[1].splitlines()
                         if l.startswith("omnishadow: ") and "warning:" not in l), ""),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("binary")
    parser.add_argument("suite")
    parser.add_argument("--timeout", type=float, default=30.0)
    parser.add_argument("--size", type=int, default=32)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--json", help="write every file's result here")
    o = parser.parse_args()
    files = sorted(os.path.join(d, f) for d, _, names in os.walk(o.suite) for f in names
                   if f.endswith((".gltf", ".glb")))
    with concurrent.futures.ThreadPoolExecutor(o.jobs) as pool:
        results = list(pool.map(lambda f: check(o.binary, f, o.timeout, o.size), files))

    def count(key, value):
        return sum(1 for r in results if r[key] == value)

    print("%d files (%d with expected errors)" %
          (len(results), sum(1 for r in results if r["errors"])))
    for key in ("info", "render"):
        statuses = sorted({str(r[key]) for r in results})
        print("%-6s " % key + ", ".join("exit %s: %d" % (s, sum(1 for r in results
                                                                if str(r[key]) == s))
                                        for s in statuses))
    bad = [r for r in results if r["problems"]]
    silent = [r for r in results if r["silent"]]
    warned = [r for r in results if r["errors"] and r["render"] == 0 and r["warned"]]
    print("crashes, hangs, malformed errors: %d" % len(bad))
    for r in bad:
        print("  %s: %s" % (os.path.relpath(r["file"], o.suite), "; ".join(r["problems"])))
    print("exit 0 on a file with expected errors, with a warning: %d" % len(warned))
    print("exit 0 on a file with expected errors, no warning: %d" % len(silent))
    for r in silent:
        print("  %s: %s" % (os.path.relpath(r["file"], o.suite), ", ".join(r["codes"])))
    valid_refused = [r for r in results if r["errors"] == 0 and r["render"] != 0]
    print("render refused a file without expected errors: %d" % len(valid_refused))
    for r in valid_refused:
        print("  %s: %s" % (os.path.relpath(r["file"], o.suite), r["message"][:160]))
    if o.json:
        with open(o.json, "w", encoding="utf-8") as f:
            json.dump(results, f, indent=1)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
