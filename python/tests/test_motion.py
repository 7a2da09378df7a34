"""load_scene(time=, animation=) poses the scene as the CLI's --time and --animation do."""

import json

import numpy as np
import pytest

import omnishadow
from conftest import SOURCE_DIR, cli_error, run_cli

KHRONOS = SOURCE_DIR / "scenes" / "khronos"
SKIN = KHRONOS / "SimpleSkin" / "SimpleSkin.gltf"
INTERPOLATION = KHRONOS / "InterpolationTest" / "InterpolationTest.glb"
STILL = KHRONOS / "MorphPrimitivesTest" / "MorphPrimitivesTest.glb"
VIEW = {"eye": (0, 1, 5), "target": (0, 1, 0)}
CLI_VIEW = ["--eye", "0,1,5", "--target", "0,1,0", "--width", 48, "--height", 48]


@pytest.mark.parametrize("time", [1.0, 4.0])
def test_posed_render_equals_the_cli_at_the_same_time(binary, renderer, tmp_path, time):
    status, _, stderr = run_cli(binary, "render", SKIN, "--time", time, *CLI_VIEW,
                                "-o", tmp_path / "cli.png", "--aov", tmp_path / "cli.exr",
                                "--camera-json")
    assert status == 0, stderr
    scene = omnishadow.load_scene(SKIN, time=time)
    frame = renderer.render(scene, camera=VIEW, width=48, height=48, aovs=[])
    frame.save(tmp_path / "py.png")
    assert frame.camera == json.loads((tmp_path / "cli.camera.json").read_text())
    assert frame.camera["time"] == time
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    aov, names = omnishadow.read_image(tmp_path / "cli.exr")
    for axis in "XYZ":  # the posed surface's world positions
        np.testing.assert_array_equal(frame["P." + axis], aov[:, :, names.index("P." + axis)])


def test_the_pose_moves_the_skin(renderer):
    positions = []
    for time in (None, 1.0, 4.0):
        frame = renderer.render(omnishadow.load_scene(SKIN, time=time), camera=VIEW, width=48,
                                height=48, aovs=[])
        covered = frame.beauty[:, :, 3] > 0
        assert covered.any()
        positions.append(frame["P.X"][covered].mean())
    rest, bent_one_way, bent_the_other = positions
    # The strip's upper half bends to one side at t = 1 and to the other at t = 4.
    assert (bent_one_way - rest) * (bent_the_other - rest) < 0


def test_animation_by_index_or_name_picks_the_clip(renderer):
    def beauty(**pose):
        scene = omnishadow.load_scene(INTERPOLATION, **pose)
        return renderer.render(scene, width=32, height=32).beauty

    np.testing.assert_array_equal(beauty(time=0.7, animation=1), beauty(time=0.7, animation="1"))
    np.testing.assert_array_equal(beauty(time=0.7, animation=1),
                                  beauty(time=0.7, animation="Linear Scale"))
    assert not np.array_equal(beauty(time=0.7, animation="all"), beauty())


@pytest.mark.parametrize("pose, cli_args", [
    ({"animation": 1}, ["--animation", "1"]),
    ({"animation": "Walk", "time": 1}, ["--time", "1", "--animation", "Walk"]),
    ({"time": float("nan")}, ["--time", "nan"]),
    ({"time": float("inf")}, ["--time", "inf"]),
])
def test_bad_time_or_animation_raises_the_cli_message(binary, tmp_path, pose, cli_args):
    expected = cli_error(binary, "render", INTERPOLATION, *cli_args, "-o", tmp_path / "a.png")
    with pytest.raises(omnishadow.InputError) as error:
        omnishadow.load_scene(INTERPOLATION, **pose)
    assert str(error.value) == expected


def test_time_and_animation_types_are_checked():
    with pytest.raises(TypeError, match="time"):
        omnishadow.load_scene(INTERPOLATION, time="1")
    with pytest.raises(TypeError, match="animation"):
        omnishadow.load_scene(INTERPOLATION, time=1, animation=1.5)


def test_time_on_a_file_without_animations_warns_like_the_cli(binary, renderer, tmp_path):
    status, _, stderr = run_cli(binary, "render", STILL, "--time", 1, "--width", 8,
                                "--height", 8, "-o", tmp_path / "a.png")
    assert status == 0, stderr
    warning = next(line for line in stderr.splitlines() if "has no animations" in line)
    frame = renderer.render(omnishadow.load_scene(STILL, time=1), width=8, height=8)
    assert "omnishadow: warning: " + frame.warnings[
        [i for i, w in enumerate(frame.warnings) if "has no animations" in w][0]] == warning


# Scene.posed(time) poses a loaded scene anew without reading the file: the same scene as a
# load at that time, from the rest pose or from another pose, and the scene it came from
# keeps its own pose.
@pytest.mark.parametrize("start", [None, 4.0])
def test_posed_equals_a_load_at_that_time(renderer, start):
    loaded = omnishadow.load_scene(SKIN, time=start)

    def seen(scene):
        frame = renderer.render(scene, camera=VIEW, width=48, height=48, aovs=[])
        return frame.beauty, frame["P.X"], frame.camera["time"]

    before = seen(loaded)
    for time in (None, 1.0, 4.0):
        posed, fresh = seen(loaded.posed(time)), seen(omnishadow.load_scene(SKIN, time=time))
        np.testing.assert_array_equal(posed[0], fresh[0])
        np.testing.assert_array_equal(posed[1], fresh[1])
        assert posed[2] == fresh[2] == time
    after = seen(loaded)
    np.testing.assert_array_equal(after[0], before[0])
    np.testing.assert_array_equal(after[1], before[1])


def test_posed_picks_clips_and_raises_like_a_load():
    interpolation = omnishadow.load_scene(INTERPOLATION)
    linear = interpolation.posed(0.7, animation="Linear Scale")
    assert linear.warnings == omnishadow.load_scene(INTERPOLATION, time=0.7,
                                                    animation="Linear Scale").warnings
    for pose in ({"time": None, "animation": 1}, {"time": 1, "animation": "Walk"},
                 {"time": float("nan")}):
        with pytest.raises(omnishadow.InputError) as posing:
            interpolation.posed(**pose)
        with pytest.raises(omnishadow.InputError) as loading:
            omnishadow.load_scene(INTERPOLATION, **pose)
        assert str(posing.value) == str(loading.value)
    with pytest.raises(TypeError, match="time"):
        interpolation.posed("1")
    with pytest.raises(TypeError, match="animation"):
        interpolation.posed(1, animation=1.5)


# A pose's warnings are those of its own time: a scene posed at a time of a file without
# animations warns once, and posed back at rest, not at all.
def test_posed_keeps_the_loaders_warnings_and_only_its_own_pose_warnings():
    still = omnishadow.load_scene(STILL)
    timed = still.posed(1.0)
    assert timed.warnings == omnishadow.load_scene(STILL, time=1.0).warnings
    assert sum("has no animations" in w for w in timed.warnings) == 1
    assert sum("has no animations" in w for w in timed.posed(2.0).warnings) == 1
    assert timed.posed(None).warnings == still.warnings
