"""Many renders with one Renderer keep memory stable (the batch use case)."""

import gc

import omnishadow
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
