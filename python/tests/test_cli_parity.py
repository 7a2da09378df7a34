"""The module's arrays and files equal what the CLI writes for the same job."""

import json

import numpy as np
import pytest

import omnishadow
from conftest import DEMO_LIGHTS, DEMO_SCENE, run_cli

WIDTH, HEIGHT = 64, 48


def render_both(binary, renderer, demo_scene, tmp_path, *cli_args, **render_args):
    status, _, stderr = run_cli(
        binary, "render", DEMO_SCENE, "-l", DEMO_LIGHTS, "--width", WIDTH, "--height", HEIGHT,
        "-o", tmp_path / "cli.png", "-o", tmp_path / "cli_beauty.exr",
        "--aov", tmp_path / "cli_aov.exr", *cli_args)
    assert status == 0, stderr
    frame = renderer.render(demo_scene, DEMO_LIGHTS, width=WIDTH, height=HEIGHT, **render_args)
    return frame


def test_beauty_and_aovs_equal_the_cli_files(binary, renderer, demo_scene, tmp_path):
    frame = render_both(binary, renderer, demo_scene, tmp_path,
                        "--aov-layers", "objectId,materialId,albedo", "--exposure", "0.5",
                        aovs=["objectId", "materialId", "albedo"], exposure=0.5)
    assert frame.beauty.shape == (HEIGHT, WIDTH, 4) and frame.beauty.dtype == np.float32

    png, channels = omnishadow.read_image(tmp_path / "cli.png")
    assert channels == ["R", "G", "B"]
    srgb = frame.to_srgb8()
    assert srgb.shape == (HEIGHT, WIDTH, 3) and srgb.dtype == np.uint8
    np.testing.assert_array_equal(srgb, np.round(png * 255).astype(np.uint8))

    aov, names = omnishadow.read_image(tmp_path / "cli_aov.exr")
    assert sorted(names) == sorted(frame.channels)
    for i, name in enumerate(names):
        np.testing.assert_array_equal(frame[name], aov[:, :, i], err_msg=name)
    # The beauty is the AOV file's RGBA, before exposure.
    rgba = np.stack([aov[:, :, names.index(c)] for c in "RGBA"], axis=-1)
    np.testing.assert_array_equal(frame.beauty, rgba)

    # Groups and typed views of the same channels.
    p = frame["P"]
    assert p.shape == (HEIGHT, WIDTH, 3)
    np.testing.assert_array_equal(p[:, :, 1], aov[:, :, names.index("P.Y")])
    np.testing.assert_array_equal(frame.depth, aov[:, :, names.index("Z")])
    assert frame["visibility"].shape == (HEIGHT, WIDTH, 2)  # the demo's two lights
    object_id = frame.object_id
    assert object_id.dtype == np.int32
    np.testing.assert_array_equal(object_id, aov[:, :, names.index("objectId")].astype(np.int32))
    assert object_id.min() >= -1 and object_id.max() < demo_scene.instance_count
    np.testing.assert_array_equal(frame.material_id,
                                  aov[:, :, names.index("materialId")].astype(np.int32))

    sidecar = json.loads((tmp_path / "cli_aov.ids.json").read_text())
    assert frame.ids == sidecar


def test_saved_files_are_byte_identical_to_the_cli(binary, renderer, demo_scene, tmp_path):
    frame = render_both(binary, renderer, demo_scene, tmp_path, aovs=[])
    frame.save(tmp_path / "py.png")
    frame.save(tmp_path / "py_beauty.exr")
    frame.save_aovs(tmp_path / "py_aov.exr")
    for cli, py in [("cli.png", "py.png"), ("cli_beauty.exr", "py_beauty.exr"),
                    ("cli_aov.exr", "py_aov.exr")]:
        assert (tmp_path / cli).read_bytes() == (tmp_path / py).read_bytes(), py


def test_arrays_own_their_memory_and_rows_are_top_first(renderer, tmp_path):
    from gltf_scene import QuadScene
    scene = QuadScene(8, 6)
    scene.add_quad(0, 0, 8, 2)  # the top two rows only
    path = scene.write(tmp_path / "top.gltf")
    frame = renderer.render(omnishadow.load_scene(path), width=8, height=6, aovs=[])
    beauty = frame.beauty
    assert beauty.flags.owndata and beauty.flags.writeable
    np.testing.assert_array_equal(beauty[:2, :, 3], 1.0)
    np.testing.assert_array_equal(beauty[2:, :, 3], 0.0)
    del frame  # the arrays outlive the frame
    beauty += 1
    assert beauty[0, 0, 3] == 2.0


def test_camera_matches_the_request(renderer, demo_scene):
    frame = renderer.render(demo_scene, width=40, height=20,
                            camera={"eye": (0, 1, 6), "target": (0, 1, 0), "fov": 60})
    camera = frame.camera
    assert (camera["width"], camera["height"]) == (40, 20)
    eye = np.array(camera["opengl"]["cameraToWorld"])[:3, 3]
    np.testing.assert_allclose(eye, (0.0, 1.0, 6.0), atol=1e-5)
    view = np.array(camera["opengl"]["worldToCamera"])
    assert np.allclose(view @ [0, 1, 0, 1], [0, 0, -6, 1], atol=1e-5)
    k = camera["intrinsics"]
    assert np.isclose(k["fy"], 10 / np.tan(np.radians(30)), rtol=1e-5)
    assert (k["cx"], k["cy"]) == (20.0, 10.0)
    assert {"upload", "shadow maps", "lighting", "readback"} <= set(frame.times)


def test_each_finished_stage_has_its_wait_for_the_gpu(renderer, demo_scene):
    size = {"width": 40, "height": 20}
    finished = renderer.render(demo_scene, finish_each_stage="on", **size)
    # Each GL stage's wait for the GPU is a part of that stage's time.
    assert {"upload", "shadow maps", "lighting"} <= set(finished.gpu_waits)
    for stage, wait in finished.gpu_waits.items():
        assert 0.0 <= wait <= finished.times[stage]
    # Unfinished, the upload and the shadow maps are waited for in the lighting: the same picture.
    flushed = renderer.render(demo_scene, finish_each_stage="off", **size)
    assert set(flushed.gpu_waits) == {"lighting"}
    np.testing.assert_array_equal(flushed.beauty, finished.beauty)


@pytest.mark.parametrize("cli_args, render_args", [
    (["--eye", "0,1,6", "--target", "0,1,0", "--fov", "60"],
     {"camera": {"eye": (0, 1, 6), "target": (0, 1, 0), "fov": 60}}),
    ([], {}),  # the framing of the whole scene
])
def test_camera_equals_the_cli_sidecar(binary, renderer, demo_scene, tmp_path, cli_args,
                                       render_args):
    status, _, stderr = run_cli(binary, "render", DEMO_SCENE, "--width", 40, "--height", 20,
                                *cli_args, "-o", tmp_path / "a.png", "--camera-json")
    assert status == 0, stderr
    sidecar = json.loads((tmp_path / "a.camera.json").read_text())
    frame = renderer.render(demo_scene, width=40, height=20, **render_args)
    assert frame.camera == sidecar
    assert list(frame.camera) == list(sidecar)  # key order too


def test_lights_from_python_data_render_like_the_file(renderer, demo_scene):
    data = json.loads(DEMO_LIGHTS.read_text())
    from_file = renderer.render(demo_scene, DEMO_LIGHTS, width=32, height=24)
    from_dict = renderer.render(demo_scene, data, width=32, height=24)
    from_list = renderer.render(demo_scene, omnishadow.load_lights(data["lights"]),
                                width=32, height=24)
    np.testing.assert_array_equal(from_file.beauty, from_dict.beauty)
    if "ambient" not in data:
        np.testing.assert_array_equal(from_file.beauty, from_list.beauty)


def test_shadow_maps_on_request(renderer, demo_scene):
    frame = renderer.render(demo_scene, DEMO_LIGHTS, width=16, height=16, shadow_maps=True)
    maps = frame.shadow_maps
    assert maps, "the demo's point lights cast shadows"
    for light, entry in maps.items():
        distances = entry["distances"]
        assert distances.ndim == 3 and distances.shape[0] == 6
        assert distances.shape[1] == distances.shape[2]
        finite = distances[np.isfinite(distances)]
        assert finite.size and finite.min() > 0 and finite.max() <= entry["far"] * 1.001
    assert renderer.render(demo_scene, DEMO_LIGHTS, width=16, height=16).shadow_maps == {}
