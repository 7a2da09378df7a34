"""Many renders with one Renderer keep memory stable (the batch use case)."""

import gc
import json
import os
import subprocess
import sys

import omnishadow
from conftest import DEMO_LIGHTS, DEMO_SCENE
from gltf_scene import QuadScene


def rss_kib():
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS in /proc/self/status")


def test_1000_renders_do_not_grow_memory(renderer, tmp_path):
    scene = QuadScene(16, 16)
    scene.add_quad(2, 2, 10, 10, node="a")
    scene.add_quad(6, 6, 14, 14, z=1.0, node="b")
    loaded = omnishadow.load_scene(scene.write(tmp_path / "quads.gltf"))
    lights = [{"name": "lamp", "type": "point", "position": [0, 0, 5], "intensity": 10,
               "shadow": {"resolution": 64}}]
    for _ in range(50):  # warm up: shader variants, pools, allocator arenas
        renderer.render(loaded, lights, width=16, height=16, aovs=["objectId"]).beauty
    gc.collect()
    before = rss_kib()
    for _ in range(1000):
        frame = renderer.render(loaded, lights, width=16, height=16, aovs=["objectId"])
        frame.beauty, frame.object_id, frame["visibility.lamp"]
    gc.collect()
    grown = rss_kib() - before
    # A leak of one 16x16 frame per render (several KiB each) would pass 4 MiB by far.
    assert grown < 4096, f"RSS grew by {grown} KiB over 1000 renders"


# use_rendering_heap() changes the process for good, so each check runs in a child interpreter.
HEAP_CHILD = r"""
import json, sys
import numpy as np
import omnishadow

def mapping(address):
    with open("/proc/self/maps") as maps:
        for line in maps:
            fields = line.split()
            begin, end = (int(x, 16) for x in fields[0].split("-"))
            if begin <= address < end:
                return fields[5] if len(fields) > 5 else ""
    return None

def large_block():
    block = np.ones(64 << 20, dtype=np.uint8)
    return mapping(block.ctypes.data)

scene_path, lights_path, set_up = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
renderer = omnishadow.Renderer()
scene = omnishadow.load_scene(scene_path)
lights = omnishadow.load_lights(lights_path)
before = renderer.render(scene, lights, width=96, height=64).beauty
result = {"before": large_block()}
if set_up:
    result["first"] = omnishadow.use_rendering_heap()
    result["second"] = omnishadow.use_rendering_heap()
result["after"] = large_block()
after = renderer.render(scene, lights, width=96, height=64).beauty
result["same_pixels"] = bool(np.array_equal(before, after))
print(json.dumps(result))
"""


def run_heap_child(set_up, extra_env=None):
    env = dict(os.environ, **(extra_env or {}))
    args = [str(DEMO_SCENE), str(DEMO_LIGHTS), "1" if set_up else "0"]
    done = subprocess.run([sys.executable, "-c", HEAP_CHILD, *args], capture_output=True,
                          text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_use_rendering_heap_serves_large_blocks_from_the_kept_heap():
    control = run_heap_child(set_up=False)
    assert control["before"] != "[heap]" and control["after"] != "[heap]", control
    result = run_heap_child(set_up=True)
    assert result["before"] != "[heap]", result
    assert result["after"] == "[heap]", result
    assert result["first"]["applied"] and result["first"]["page_fault_us"] > 0.0, result
    assert result["second"] == result["first"], result
    assert result["same_pixels"], result
    assert control["same_pixels"], control


def test_use_rendering_heap_can_be_turned_off():
    result = run_heap_child(set_up=True, extra_env={"OMNISHADOW_MEMORY_WARMUP": "0"})
    assert result["first"] == {"applied": False, "page_fault_us": 0.0, "huge_pages": False}, result
    assert result["after"] != "[heap]", result
    assert result["same_pixels"], result
