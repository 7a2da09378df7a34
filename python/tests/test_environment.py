"""Environment lighting through the module: the same pixels as the CLI, the lights file's
fields as a dict, and the error of an image that cannot be read."""

import numpy as np
import pytest

import omnishadow
from conftest import SOURCE_DIR, cli_render_demo

SKY = SOURCE_DIR / "scenes" / "environments" / "sky.exr"


def test_the_module_and_the_cli_render_the_same_environment(binary, renderer, demo_scene,
                                                            tmp_path):
    setup = {"environment": {"image": str(SKY), "intensity": 1.5, "rotation": 30,
                             "background": True},
             "lights": [{"name": "sun", "type": "directional", "direction": [-1, -1, -1],
                         "intensity": 2}]}
    png, channels = cli_render_demo(binary, setup, tmp_path, 64, 48)
    frame = renderer.render(demo_scene, omnishadow.load_lights(setup), width=64, height=48)
    assert channels == ["R", "G", "B"]
    np.testing.assert_array_equal(frame.to_srgb8(), np.round(png * 255).astype(np.uint8))
    # The background makes every pixel opaque.
    assert (frame.beauty[:, :, 3] == 1.0).all()


def test_lights_report_their_environment():
    lights = omnishadow.load_lights({"environment": {"image": str(SKY), "rotation": 90,
                                                     "color": [1, 0.5, 0.25]}})
    assert lights.environment == pytest.approx(
        {"image": str(SKY), "color": (1.0, 0.5, 0.25), "intensity": 1.0, "rotation": 90.0,
         "background": False, "sun": False})
    assert lights.ambient == (0.0, 0.0, 0.0)
    assert omnishadow.load_lights({"lights": []}).environment is None


def test_an_unreadable_image_is_an_input_error(renderer, demo_scene, tmp_path):
    lights = omnishadow.load_lights({"environment": {"image": str(tmp_path / "missing.exr")}},
                                    label="rig")
    with pytest.raises(omnishadow.InputError, match=r"^rig: environment\.image: .*missing\.exr"):
        renderer.render(demo_scene, lights, width=8, height=8)
