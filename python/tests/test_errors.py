"""Bad input raises omnishadow.InputError (a ValueError) with the CLI's one-line message."""

import json

import numpy as np
import pytest

import omnishadow
from conftest import DEMO_LIGHTS, DEMO_SCENE, cli_error


def test_error_classes():
    assert issubclass(omnishadow.InputError, ValueError)
    assert issubclass(omnishadow.RenderError, RuntimeError)
    assert not issubclass(omnishadow.InputError, omnishadow.RenderError)


BAD_LIGHTS = [
    {"lights": [{"name": "a", "type": "point", "position": [0, 1]}]},
    {"lights": [{"name": "a", "type": "lamp", "position": [0, 1, 2]}]},
    {"lights": [{"name": "a", "type": "point", "position": [0, 1, 2], "intensity": -1}]},
    {"lights": [{"name": "a", "position": [0, 1, 2]}, {"name": "a", "position": [0, 1, 2]}]},
    {"lights": [{"name": "a", "position": [0, 1, 2], "shadow": {"filter": "blurry"}}]},
    {"ambient": [0, 0], "lights": []},
]


@pytest.mark.parametrize("content", BAD_LIGHTS)
def test_bad_lights_file_and_data_give_the_cli_message(binary, tmp_path, content):
    path = tmp_path / "bad.lights.json"
    path.write_text(json.dumps(content))
    expected = cli_error(binary, "render", DEMO_SCENE, "-l", path, "--width", 8, "--height", 8,
                         "-o", tmp_path / "out.png")
    assert expected.startswith(str(path) + ": ")
    with pytest.raises(omnishadow.InputError) as from_file:
        omnishadow.load_lights(path)
    assert str(from_file.value) == expected
    # The same data from Python: the same message, the label standing for the file name.
    with pytest.raises(omnishadow.InputError) as from_data:
        omnishadow.load_lights(content, label=str(path))
    assert str(from_data.value) == expected
    assert not (tmp_path / "out.png").exists()


def test_bad_scene_files_give_the_cli_message(binary, tmp_path):
    missing = tmp_path / "missing.gltf"
    broken = tmp_path / "broken.gltf"
    broken.write_text('{"asset": {"version": "2.0"}, "nodes": [{"mesh": 3}], "scenes": '
                      '[{"nodes": [0]}]}')
    empty = tmp_path / "empty.gltf"
    empty.write_text('{"asset": {"version": "2.0"}, "nodes": [{}], "scenes": [{"nodes": [0]}]}')
    for scene in (missing, broken, empty):
        expected = cli_error(binary, "render", scene, "--width", 8, "--height", 8,
                             "-o", tmp_path / "out.png")
        with pytest.raises(omnishadow.InputError) as error:
            omnishadow.load_scene(scene)
        assert str(error.value) == expected


def test_render_arguments_give_the_cli_message(binary, renderer, demo_scene, tmp_path):
    expected = cli_error(binary, "render", DEMO_SCENE, "--camera", "nope", "--width", 8,
                         "--height", 8, "-o", tmp_path / "out.png")
    with pytest.raises(omnishadow.InputError) as error:
        renderer.render(demo_scene, camera="nope", width=8, height=8)
    assert str(error.value) == expected

    expected = cli_error(binary, "render", DEMO_SCENE, "--eye", "0,1,2", "--target", "0,1,2",
                         "--width", 8, "--height", 8, "-o", tmp_path / "out.png")
    with pytest.raises(omnishadow.InputError) as error:
        renderer.render(demo_scene, camera={"eye": (0, 1, 2), "target": (0, 1, 2)}, width=8,
                        height=8)
    assert str(error.value) == expected

    expected = cli_error(binary, "render", DEMO_SCENE, "-l", DEMO_LIGHTS, "--max-memory", "1",
                         "--width", 8, "--height", 8, "-o", tmp_path / "out.png")
    with pytest.raises(omnishadow.InputError) as error:
        renderer.render(demo_scene, DEMO_LIGHTS, width=8, height=8, max_memory=1)
    assert str(error.value) == expected


@pytest.mark.parametrize("arguments, message", [
    ({"aovs": ["albedo", "sparkle"]}, 'aovs: unknown layer "sparkle"'),
    ({"shading": "toon"}, "shading toon: expected pbr or phong"),
    ({"shadow_pass": "all"}, "shadow_pass all: expected auto, six, geometry, instanced or batched"),
    ({"depth_prepass": "yes"}, "depth_prepass yes: expected auto, on or off"),
    ({"finish_each_stage": "later"}, "finish_each_stage later: expected auto, on or off"),
    ({"exposure": float("nan")}, "exposure nan: expected a finite number of stops"),
    ({"width": 0}, "width 0: expected a size from 1 to 16384"),
    ({"camera": {"eye": (0, 1)}}, 'camera["eye"]: expected 3 finite numbers'),
    ({"camera": {"position": (0, 1, 2)}}, 'camera["position"]: unknown key'),
    ({"camera": 2.5}, "camera: expected None, a glTF camera name or index, or a dict"),
    ({"lights": 42}, "lights: expected a lights file path"),
    ({"lights": [{"name": "a", "position": [0, float("inf"), 0]}]}, "lights: Out of range float"),
    ({"lights": [{"name": "a", "position": np.array([0.0, 1.0, 2.0]), "intensity": -1}]},
     "lights: lights[0].intensity"),
])
def test_python_arguments_raise_input_error(renderer, demo_scene, arguments, message):
    with pytest.raises(omnishadow.InputError) as error:
        renderer.render(demo_scene, **{"width": 8, "height": 8, **arguments})
    assert str(error.value).startswith(message)


def test_unwritable_output_is_a_render_error(renderer, demo_scene, tmp_path):
    frame = renderer.render(demo_scene, width=8, height=8)
    (tmp_path / "a_file").write_text("")
    with pytest.raises(omnishadow.RenderError, match="a_file"):
        frame.save(tmp_path / "a_file" / "out.png")  # even root cannot make this folder
    with pytest.raises(omnishadow.InputError, match="unsupported image format"):
        frame.save(tmp_path / "out.jpg")
    with pytest.raises(KeyError, match="no AOVs"):
        frame["P"]
    assert "P" not in frame
