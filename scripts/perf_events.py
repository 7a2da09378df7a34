"""perf helpers shared by the measuring scripts (frame_cpu.py, first_frame_calls.py): their
common options, the renderer's functions found in the binary, uprobes added and removed, and a
command run under `perf record` with its samples and probe hits read back as events."""
import os
import re
import subprocess
import sys


def add_scene_arguments(parser):
    """--bin, --peers, --scenes, --filter and --size, as the measuring scripts take them: the
    bench scenes of ../shared/peers/compare.py with its lights."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--bin", default=os.path.join(root, "build", "omnishadow"))
    parser.add_argument("--peers", default=os.path.join(root, "..", "shared", "peers"))
    parser.add_argument("--scenes", default="box,cornell,sundial,whackamole,test_room")
    parser.add_argument("--filter", default="pcf")
    parser.add_argument("--size", default="1280x720")


def function_addresses(binary, name):
    """The addresses of the functions omnishadow::<name>(...), GCC's .cold parts left out."""
    mangled = subprocess.run(["nm", binary], capture_output=True, text=True, check=True).stdout
    demangled = subprocess.run(["nm", "-C", binary], capture_output=True, text=True,
                               check=True).stdout
    found = set()
    for raw, readable in zip(mangled.splitlines(), demangled.splitlines()):
        fields = raw.split()
        if len(fields) != 3 or fields[1] not in "Tt" or "." in fields[2]:
            continue
        text = readable.split(" ", 2)[2] if readable.count(" ") >= 2 else ""
        # Not the lambdas defined inside it ("name(...)::{lambda...}::operator()").
        if (text.startswith(f"omnishadow::{name}(") or text.startswith(
                f"omnishadow::(anonymous namespace)::{name}(")) and ")::" not in text:
            found.add(fields[0])
    return sorted(found)


def add_probes(who, binary, specs):
    """Adds the uprobes `specs` ("group:event=address[%return]") on `binary`; exits naming `who`
    when perf cannot."""
    args = ["perf", "probe", "-q", "-x", binary]
    for spec in specs:
        args += ["-a", spec]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"{who}: perf probe failed (root or perf_event_paranoid <= 1 needed):\n"
                 f"{p.stderr.strip()}")


def record_events(who, record_args, data, command):
    """Runs `perf record -q <record_args> -o <data> -- <command>` and returns its events as
    (comm, pid, tid, seconds, event name) tuples; exits naming `who` when the command fails."""
    cmd = ["perf", "record", "-q", *record_args, "-o", data, "--", *command]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"{who}: {' '.join(cmd)} failed:\n{p.stderr.strip()}")
    script = subprocess.run(["perf", "script", "-i", data, "-F", "comm,pid,tid,time,event"],
                            capture_output=True, text=True, check=True).stdout
    events = []
    for line in script.splitlines():
        m = re.match(r"\s*(\S+)\s+(\d+)/(\d+)\s+([\d.]+):\s+(\S+):", line)
        if m:
            events.append((m[1], int(m[2]), int(m[3]), float(m[4]), m[5]))
    return events


def remove_probes(group):
    subprocess.run(["perf", "probe", "-q", "-d", f"{group}:*"], capture_output=True)
