"""Shadow maps on request for every light type: the values --dump-depth writes, with the
distances the geometry gives."""

import json

import numpy as np
import pytest

import omnishadow
from conftest import run_cli
from gltf_scene import QuadScene

SIZE = 32
# A floor at z = 0 under the whole view and an 8 x 8 occluder at z = 2 in its middle, seen by
# the orthographic camera at z = 10; the lights look down -Z from z = 10.
LIGHTS = {"lights": [
    {"name": "spot", "type": "spot", "position": [0, 0, 10], "direction": [0, 0, -1],
     "outerConeAngle": 0.6, "intensity": 50, "shadow": {"resolution": 64}},
    {"name": "sun", "type": "directional", "direction": [0, 0, -1], "intensity": 2,
     "shadow": {"resolution": 48, "cascades": 2}},
    {"name": "bulb", "type": "point", "position": [3, 3, 6], "intensity": 20,
     "shadow": {"resolution": 16}},
]}


@pytest.fixture(scope="module")
def occluder_scene(tmp_path_factory):
    scene = QuadScene(SIZE, SIZE)
    scene.add_quad(0, 0, SIZE, SIZE, z=0.0, node="floor")
    scene.add_quad(12, 12, 20, 20, z=2.0, node="box")
    folder = tmp_path_factory.mktemp("shadow_maps")
    lights = folder / "lights.json"
    lights.write_text(json.dumps(LIGHTS))
    return scene.write(folder / "scene.gltf"), lights


def test_every_light_type_equals_the_depth_dump(binary, renderer, occluder_scene, tmp_path):
    path, lights = occluder_scene
    status, _, stderr = run_cli(binary, "render", path, "-l", lights, "--width", SIZE,
                                "--height", SIZE, "-o", tmp_path / "a.png",
                                "--dump-depth", tmp_path / "dump")
    assert status == 0, stderr
    frame = renderer.render(omnishadow.load_scene(path), LIGHTS, width=SIZE, height=SIZE,
                            shadow_maps=True)
    maps = frame.shadow_maps
    assert sorted(maps) == ["bulb", "spot", "sun"]

    def dumped(base):
        image, channels = omnishadow.read_image(tmp_path / "dump" / f"{base}.exr")
        assert channels == ["Z"]
        return image[:, :, 0]

    spot = maps["spot"]
    assert spot["type"] == "spot" and spot["distances"].shape == (64, 64)
    assert spot["distances"].dtype == np.float32
    np.testing.assert_array_equal(spot["distances"], dumped("spot_spot"))

    sun = maps["sun"]
    assert sun["type"] == "directional" and len(sun["cascades"]) == 2
    for i, cascade in enumerate(sun["cascades"]):
        assert cascade["distances"].shape == (48, 48)
        np.testing.assert_array_equal(cascade["distances"], dumped(f"sun_cascade{i}"))

    bulb = maps["bulb"]
    assert bulb["type"] == "point" and bulb["distances"].shape == (6, 16, 16)
    for f, face in enumerate(bulb["faces"]):
        np.testing.assert_array_equal(bulb["distances"][f], dumped(f"bulb_{face}"))


def test_the_occluder_is_where_the_geometry_says(renderer, occluder_scene):
    path, _ = occluder_scene
    frame = renderer.render(omnishadow.load_scene(path), LIGHTS, width=SIZE, height=SIZE,
                            shadow_maps=True)
    # The spot map's distances run along its axis (-Z from z = 10): the occluder at 8, the floor
    # at 10 everywhere else in the cone (it reaches far beyond the cone's edge).
    spot = frame.shadow_maps["spot"]["distances"]
    centre = spot[28:36, 28:36]
    np.testing.assert_allclose(centre, 8.0, rtol=1e-4)
    corners = np.concatenate([spot[:4, :4].ravel(), spot[-4:, -4:].ravel()])
    np.testing.assert_allclose(corners, 10.0, rtol=1e-4)
    assert spot.max() <= frame.shadow_maps["spot"]["far"]
    # Each cascade sees the occluder's top and the floor, 2 apart along the sun's direction.
    for cascade in frame.shadow_maps["sun"]["cascades"]:
        finite = cascade["distances"][np.isfinite(cascade["distances"])]
        levels = np.unique(np.round(finite, 3))
        assert len(levels) == 2, levels
        assert levels[1] - levels[0] == pytest.approx(2.0, abs=2e-3)


@pytest.mark.parametrize("shadow_pass", ["instanced", "geometry", "batched"])
def test_every_shadow_pass_gives_the_maps_six_gives(renderer, occluder_scene, shadow_pass):
    path, _ = occluder_scene
    scene = omnishadow.load_scene(path)
    lights = {"lights": LIGHTS["lights"] + [
        {"name": "bulb2", "type": "point", "position": [-3, 2, 5], "intensity": 20,
         "shadow": {"resolution": 16}}]}
    six = renderer.render(scene, lights, width=SIZE, height=SIZE, shadow_maps=True,
                          shadow_pass="six")
    other = renderer.render(scene, lights, width=SIZE, height=SIZE, shadow_maps=True,
                            shadow_pass=shadow_pass)
    for name in ("bulb", "bulb2", "spot"):
        np.testing.assert_array_equal(other.shadow_maps[name]["distances"],
                                      six.shadow_maps[name]["distances"])
    np.testing.assert_array_equal(other.beauty, six.beauty)


def test_the_depth_prepass_on_or_off_draws_the_same_picture(renderer, occluder_scene):
    path, _ = occluder_scene
    scene = omnishadow.load_scene(path)
    frames = {prepass: renderer.render(scene, LIGHTS, width=SIZE, height=SIZE,
                                       depth_prepass=prepass)
              for prepass in ("on", "off", "auto")}
    np.testing.assert_array_equal(frames["on"].beauty, frames["off"].beauty)
    np.testing.assert_array_equal(frames["on"].beauty, frames["auto"].beauty)
    np.testing.assert_array_equal(frames["on"].to_srgb8(), frames["off"].to_srgb8())
