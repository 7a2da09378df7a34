"""Annotation masks (--masks and render(masks=True)) are exact on constructed scenes."""

import base64
import json
import struct

import numpy as np
import pytest

import omnishadow
from conftest import run_cli
from gltf_scene import QuadScene

W, H = 32, 24


@pytest.fixture(scope="module")
def quads(tmp_path_factory):
    scene = QuadScene(W, H)
    wood = scene.material("wood")
    scene.add_quad(2, 2, 12, 10, node="table", cls="furniture", material=wood)      # 0
    scene.add_quad(8, 6, 16, 14, z=1.0, node="cup", mesh="cup_mesh")                # 1, in front
    scene.add_quad(20, 15, 30, 20, mesh="plate")                                     # 2, no name
    scene.add_quad(20, 2, 24, 6, node="chair", cls="furniture", material=wood)      # 3
    scene.add_quad(3, 3, 5, 5, z=-1.0, node="hidden")                                # 4, behind
    scene.add_quad(40, 2, 44, 6, node="offscreen")                                   # 5
    return scene.write(tmp_path_factory.mktemp("masks") / "quads.gltf")


def expected_masks():
    instances = np.zeros((H, W), np.uint16)
    instances[2:10, 2:12] = 1
    instances[6:14, 8:16] = 2
    instances[15:20, 20:30] = 3
    instances[2:6, 20:24] = 4
    # Classes in name order: cup, furniture, hidden, offscreen, plate.
    class_of = {0: 0, 1: 2, 2: 1, 3: 5, 4: 2}
    semantic = np.vectorize(class_of.get)(instances).astype(np.uint16)
    return instances, semantic


def test_masks_and_index_are_exact(renderer, quads):
    frame = renderer.render(omnishadow.load_scene(quads), width=W, height=H, masks=True)
    masks = frame.masks
    instances, semantic = expected_masks()
    assert masks["instances"].dtype == np.uint16
    np.testing.assert_array_equal(masks["instances"], instances)
    np.testing.assert_array_equal(masks["semantic"], semantic)

    index = masks["index"]
    assert index["background"] == 0
    assert index["classes"] == [{"id": 1, "name": "cup"}, {"id": 2, "name": "furniture"},
                                {"id": 3, "name": "hidden"}, {"id": 4, "name": "offscreen"},
                                {"id": 5, "name": "plate"}]
    entries = index["instances"]
    assert [e["id"] for e in entries] == [1, 2, 3, 4, 5, 6]
    assert [e["class"] for e in entries] == ["furniture", "cup", "plate", "furniture", "hidden",
                                             "offscreen"]
    assert [e["nodeName"] for e in entries] == ["table", "cup", "", "chair", "hidden",
                                                "offscreen"]
    assert entries[1]["mesh"] == "cup_mesh"
    assert entries[0]["material"] == "wood" and entries[1]["material"] == "(default)"
    # The table loses the 4 x 4 pixels the cup hides: 80 - 16 visible of 80.
    assert [e["pixels"] for e in entries] == [64, 64, 50, 16, 0, 0]
    assert [e["unoccludedPixels"] for e in entries] == [80, 64, 50, 16, 4, 0]
    assert [e["visibleFraction"] for e in entries] == [0.8, 1.0, 1.0, 1.0, 0.0, None]
    assert [e["bbox"] for e in entries] == [[2, 2, 12, 10], [8, 6, 16, 14], [20, 15, 30, 20],
                                            [20, 2, 24, 6], None, None]


def test_cli_writes_the_same_masks(binary, renderer, quads, tmp_path):
    status, _, stderr = run_cli(binary, "render", quads, "--width", W, "--height", H,
                                "-o", tmp_path / "beauty.png", "--masks", tmp_path / "m")
    assert status == 0, stderr
    frame = renderer.render(omnishadow.load_scene(quads), width=W, height=H, masks=True)
    masks = frame.masks
    for name, key in [("m.instances.png", "instances"), ("m.semantic.png", "semantic")]:
        image, channels = omnishadow.read_image(tmp_path / name)
        assert image.shape == (H, W, 1)
        np.testing.assert_array_equal(np.round(image[:, :, 0] * 65535).astype(np.uint16),
                                      masks[key], err_msg=name)
    assert json.loads((tmp_path / "m.masks.json").read_text()) == masks["index"]
    frame.save_masks(tmp_path / "py")
    for suffix in (".instances.png", ".semantic.png", ".masks.json"):
        assert (tmp_path / ("py" + suffix)).read_bytes() == (tmp_path / ("m" + suffix)).read_bytes()


@pytest.fixture(scope="module")
def see_through(tmp_path_factory):
    # Opaque, blended and masked quads: the ids of blended surfaces show only where no opaque
    # or masked one covers the pixel and their coverage (A) is above 0.
    scene = QuadScene(W, H)
    opaque = scene.material("opaque")
    glass = scene.material("glass", (0.2, 0.6, 0.9, 0.5), alpha_mode="BLEND")
    clear = scene.material("clear", (0.2, 0.6, 0.9, 0.0), alpha_mode="BLEND")
    cut = scene.material("cut", (0.5, 0.5, 0.5, 0.3), alpha_mode="MASK", alpha_cutoff=0.5)
    kept = scene.material("kept", (0.5, 0.5, 0.5, 0.8), alpha_mode="MASK", alpha_cutoff=0.5)
    scene.add_quad(2, 2, 10, 10, material=opaque)              # 0
    scene.add_quad(6, 6, 14, 14, z=1.0, material=glass)        # 1: in front of 0, then alone
    scene.add_quad(16, 2, 20, 6, z=1.0, material=clear)        # 2: covers nothing (A = 0)
    scene.add_quad(22, 2, 26, 6, material=cut)                 # 3: cut away
    scene.add_quad(22, 8, 26, 12, material=kept)               # 4
    scene.add_quad(0, 16, 6, 22, z=-1.0, material=glass)      # 5: behind 1's twin below
    scene.add_quad(3, 14, 9, 20, z=2.0, material=glass)        # 6: in front of 5
    scene.add_quad(12, 16, 20, 22, z=-1.0, material=glass)    # 7: behind an opaque one
    scene.add_quad(14, 18, 18, 22, material=opaque)            # 8
    scene.add_quad(26, 14, 30, 18, material=glass)             # 9
    scene.add_quad(27, 15, 31, 19, z=1.0, material=clear)      # 10: over 9, adds no coverage
    return scene.write(tmp_path_factory.mktemp("see_through") / "see_through.gltf")


def test_masks_after_frames_without_them_are_exact(quads):
    # One renderer keeps its targets between frames of one size; a frame with masks needs
    # one more than the plain frame before it.
    renderer = omnishadow.Renderer()
    scene = omnishadow.load_scene(quads)
    instances, _ = expected_masks()
    plain = renderer.render(scene, width=W, height=H)
    with_masks = renderer.render(scene, width=W, height=H, masks=True)
    again = renderer.render(scene, width=W, height=H)
    np.testing.assert_array_equal(with_masks.masks["instances"], instances)
    np.testing.assert_array_equal(with_masks.beauty, plain.beauty)
    np.testing.assert_array_equal(again.beauty, plain.beauty)


def test_masks_of_blended_surfaces_are_the_objectid_layers(renderer, see_through, binary,
                                                           tmp_path):
    expected = np.zeros((H, W), np.uint16)
    expected[6:14, 6:14] = 2
    expected[2:10, 2:10] = 1
    expected[8:12, 22:26] = 5
    expected[16:22, 0:6] = 6
    expected[14:20, 3:9] = 7
    expected[16:22, 12:20] = 8
    expected[18:22, 14:18] = 9
    # Where 10 lies over 9 the coverage is 9's, and the front-most blended surface is 10.
    expected[14:18, 26:30] = 10
    expected[15:18, 27:30] = 11
    scene = omnishadow.load_scene(see_through)
    alone = renderer.render(scene, width=W, height=H, masks=True)
    assert alone.channels == []  # masks alone make no AOV image
    np.testing.assert_array_equal(alone.masks["instances"], expected)
    # The AOVs' objectId layer gives the same masks.
    with_aovs = renderer.render(scene, width=W, height=H, aovs=["objectId"])
    np.testing.assert_array_equal(with_aovs["objectId"], expected.astype(np.float32) - 1)
    assert with_aovs.masks["index"] == alone.masks["index"]
    # So do the CLI's --masks alone and with --aov, file for file; the beauty too.
    for stem, extra in [("alone", []), ("aov", ["--aov", tmp_path / "a.exr"])]:
        status, _, stderr = run_cli(binary, "render", see_through, "--width", W, "--height", H,
                                    "-o", tmp_path / f"{stem}.png", "--masks", tmp_path / stem,
                                    *extra)
        assert status == 0, stderr
    for suffix in (".png", ".instances.png", ".semantic.png", ".masks.json"):
        assert (tmp_path / ("alone" + suffix)).read_bytes() == \
            (tmp_path / ("aov" + suffix)).read_bytes(), suffix
    # Masks without an image (no shadow maps, no beauty drawn) are the same files.
    status, _, stderr = run_cli(binary, "batch", see_through, "--out", tmp_path / "batch",
                                "--width", W, "--height", H, "--no-png", "--masks", "-q")
    assert status == 0, stderr
    for suffix in (".instances.png", ".semantic.png", ".masks.json"):
        assert (tmp_path / "batch" / ("see_through" + suffix)).read_bytes() == \
            (tmp_path / ("alone" + suffix)).read_bytes(), suffix


def test_masks_without_a_picture_are_the_same_and_draw_no_light(renderer, see_through, tmp_path):
    scene = omnishadow.load_scene(see_through)
    lamp = [{"name": "lamp", "type": "point", "position": [0, 0, 3], "intensity": 5,
             "shadow": {"resolution": 64}}]
    lit = renderer.render(scene, lamp, width=W, height=H, masks=True)
    alone = renderer.render(scene, lamp, width=W, height=H, masks=True, beauty=False)
    assert (alone.width, alone.height) == (W, H)
    np.testing.assert_array_equal(alone.masks["instances"], lit.masks["instances"])
    assert alone.masks["index"] == lit.masks["index"]
    assert "shadow maps" in lit.times and "lighting" in lit.times
    assert "shadow maps" not in alone.times and "lighting" not in alone.times
    for use in (lambda f: f.beauty, lambda f: f.to_srgb8(), lambda f: f.save(tmp_path / "x.png")):
        with pytest.raises(ValueError, match="beauty=False"):
            use(alone)
    assert not (tmp_path / "x.png").exists()
    # Asked for with AOVs, the picture is drawn anyway.
    with_aovs = renderer.render(scene, lamp, width=W, height=H, aovs=[], beauty=False)
    assert with_aovs.beauty.shape == (H, W, 4)


def test_more_instances_than_a_16_bit_mask_holds_are_refused(binary, renderer, tmp_path):
    # One triangle drawn 65536 times (EXT_mesh_gpu_instancing): one instance too many.
    count = 65536
    triangle = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    offsets = b"".join(struct.pack("<3f", (i % 256) * 0.01, (i // 256) * 0.01, 0)
                       for i in range(count))
    blob = triangle + offsets
    gltf = {
        "asset": {"version": "2.0"}, "extensionsUsed": ["EXT_mesh_gpu_instancing"], "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "extensions": {
            "EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 1}}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(triangle)},
                        {"buffer": 0, "byteOffset": len(triangle), "byteLength": len(offsets)}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(blob).decode()}]}
    path = tmp_path / "many.gltf"
    path.write_text(json.dumps(gltf))
    out = tmp_path / "out"
    out.mkdir()
    status, _, stderr = run_cli(binary, "render", path, "--width", 16, "--height", 16,
                                "-o", out / "a.png", "--masks", out / "m")
    assert status == 2
    assert stderr.strip().splitlines()[-1] == (
        f"omnishadow: {path}: --masks: the scene has 65536 mesh instances, more than the 65535 a "
        "16-bit mask holds")
    assert list(out.iterdir()) == []
    frame = renderer.render(omnishadow.load_scene(path), width=16, height=16, masks=True)
    with pytest.raises(omnishadow.InputError, match="65536 mesh instances"):
        frame.masks


def test_masks_need_the_objectid_layer(renderer, quads):
    frame = renderer.render(omnishadow.load_scene(quads), width=W, height=H)
    with pytest.raises(KeyError, match="no AOVs"):
        frame.masks


def test_mask_files_are_outputs_of_the_job(binary, quads, tmp_path):
    # A mask file named like another output is refused before rendering, nothing written.
    status, _, stderr = run_cli(binary, "render", quads, "--width", W, "--height", H,
                                "-o", tmp_path / "m.instances.png", "--masks", tmp_path / "m")
    assert status == 2
    assert stderr.strip() == (f"omnishadow: {tmp_path / 'm.instances.png'}: the same file is "
                              "given twice as output")
    assert list(tmp_path.iterdir()) == []


PERSPECTIVE_CASES = {
    "tilted": ([(-9.3, -4.1, 0.2), (-1.7, -5.2, -1.3), (-2.9, 3.7, 0.9), (-8.2, 2.9, 0)], False),
    # A strip of floor from far in front of the camera (z = 10) to behind it: the GPU clips it
    # at the near plane (z = 9.5) inside the view, the CPU coverage must clip it the same way.
    "through_near_plane": ([(-0.5, -0.2, -6.0), (-0.5, -0.2, 13.0), (0.5, -0.2, 13.0),
                            (0.5, -0.2, -6.0)], False),
    # Seen from behind: culled when single-sided, drawn when double-sided.
    "back_single": ([(2.2, 1.1, 1.0), (2.2, 4.3, 1.0), (6.8, 4.3, 1.0), (6.8, 1.1, 1.0)], False),
    "back_double": ([(2.2, 1.1, 1.0), (2.2, 4.3, 1.0), (6.8, 4.3, 1.0), (6.8, 1.1, 1.0)], True),
}


@pytest.mark.parametrize("name", PERSPECTIVE_CASES)
def test_unoccluded_pixels_match_the_gpu_under_perspective(renderer, tmp_path, name):
    # Alone in the scene, an instance's visible pixels are all the pixels it covers: the CPU
    # coverage (perspective, near-plane clipping, culling) must count exactly the GPU's.
    corners, double_sided = PERSPECTIVE_CASES[name]
    scene = QuadScene(48, 36, perspective_yfov=1.0)
    material = scene.material("m", double_sided=double_sided)
    scene.add_corners(corners, node=name, material=material)
    frame = renderer.render(omnishadow.load_scene(scene.write(tmp_path / "p.gltf")), width=48,
                            height=36, masks=True)
    entry = frame.masks["index"]["instances"][0]
    if name == "back_single":
        assert (entry["pixels"], entry["unoccludedPixels"]) == (0, 0)
        assert entry["visibleFraction"] is None
        return
    assert entry["pixels"] > 20
    assert entry["unoccludedPixels"] == entry["pixels"]
    assert entry["visibleFraction"] == 1.0
    if name == "through_near_plane":  # the clipped edge is in view: the bottom rows are empty
        rows = np.nonzero(frame.masks["instances"].any(axis=1))[0]
        assert rows.max() < 35


def test_a_node_without_a_class_takes_its_nearest_ancestors(binary, renderer, tmp_path):
    scene = QuadScene(W, H)
    scene.add_quad(2, 2, 6, 6, node="leg")                     # node 0: below "table"
    scene.add_quad(8, 2, 12, 6, node="top", cls="tabletop")    # node 1: below "table"
    scene.add_quad(2, 8, 6, 12, node="screw")                  # node 2: below "leg"
    scene.add_quad(20, 2, 24, 6, node="cup")                   # node 3: a root
    path = scene.write(tmp_path / "tree.gltf")
    gltf = json.loads(path.read_text())
    nodes = gltf["nodes"]
    nodes[0]["children"] = [2]
    camera = next(i for i, n in enumerate(nodes) if "camera" in n)
    table, shelf, lamp = len(nodes), len(nodes) + 1, len(nodes) + 2
    nodes.append({"name": "table", "children": [0, 1], "extras": {"class": "furniture"}})
    # A class that is no string counts as none: "lamp" takes its parent's.
    nodes.append({"name": "shelf", "children": [lamp], "extras": {"class": "storage"}})
    nodes.append({"name": "lamp", "mesh": 3, "extras": {"class": 7}, "translation": [0, -10, 0]})
    gltf["scenes"][0]["nodes"] = [table, 3, camera, shelf]
    path.write_text(json.dumps(gltf))

    frame = renderer.render(omnishadow.load_scene(path), width=W, height=H, masks=True)
    classes = {e["nodeName"]: e["class"] for e in frame.masks["index"]["instances"]}
    assert classes == {"leg": "furniture", "screw": "furniture", "top": "tabletop",
                       "cup": "cup", "lamp": "storage"}
    status, _, stderr = run_cli(binary, "render", path, "--width", W, "--height", H,
                                "-o", tmp_path / "a.png", "--masks", tmp_path / "m")
    assert status == 0, stderr
    assert json.loads((tmp_path / "m.masks.json").read_text()) == frame.masks["index"]
