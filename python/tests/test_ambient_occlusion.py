"""Ambient occlusion through the module: the same pixels as the CLI, the lights file's fields as
a dict, and the ambient light it darkens."""

import numpy as np
import pytest

import omnishadow
from conftest import cli_render_demo


def test_the_module_and_the_cli_render_the_same_occlusion(binary, renderer, demo_scene,
                                                          tmp_path):
    setup = {"ambient": [0.4, 0.4, 0.4], "ambient_occlusion": {"radius": 0.5},
             "lights": [{"name": "key", "type": "point", "position": [2, 3, 2],
                         "intensity": 30}]}
    png, _ = cli_render_demo(binary, setup, tmp_path, 96, 64)
    frame = renderer.render(demo_scene, omnishadow.load_lights(setup), width=96, height=64)
    np.testing.assert_array_equal(frame.to_srgb8(), np.round(png * 255).astype(np.uint8))


def test_occlusion_only_darkens(renderer, demo_scene):
    plain = {"ambient": [0.5, 0.5, 0.5], "lights": []}
    occluded = dict(plain, ambient_occlusion=True)
    before = renderer.render(demo_scene, omnishadow.load_lights(plain), width=96, height=64)
    after = renderer.render(demo_scene, omnishadow.load_lights(occluded), width=96, height=64)
    assert (after.beauty[:, :, :3] <= before.beauty[:, :, :3]).all()
    assert (after.beauty[:, :, :3] < before.beauty[:, :, :3] - 1e-3).any()
    np.testing.assert_array_equal(after.beauty[:, :, 3], before.beauty[:, :, 3])


def test_the_occlusion_layer(renderer, demo_scene):
    lights = omnishadow.load_lights({"ambient": [0.5, 0.5, 0.5], "ambient_occlusion": True,
                                     "lights": []})
    frame = renderer.render(demo_scene, lights, width=96, height=64, aovs=["occlusion"])
    occlusion = frame["occlusion"]
    covered = frame.beauty[:, :, 3] > 0
    assert occlusion.shape == (64, 96)
    assert (occlusion[covered] <= 1.0).all() and (occlusion[covered] < 0.9).any()
    assert (occlusion[~covered] == 0.0).all()


def test_lights_report_their_ambient_occlusion():
    assert omnishadow.load_lights({"ambient_occlusion": {"radius": 0.25, "strength": 0.5}}) \
        .ambient_occlusion == pytest.approx({"radius": 0.25, "strength": 0.5})
    assert omnishadow.load_lights({"ambient_occlusion": True}).ambient_occlusion == \
        {"radius": None, "strength": 1.0}
    assert omnishadow.load_lights({"lights": []}).ambient_occlusion is None
    with pytest.raises(omnishadow.InputError,
                       match=r"^rig: ambient_occlusion\.radius: expected a finite number > 0"):
        omnishadow.load_lights({"ambient_occlusion": {"radius": -1}}, label="rig")
