"""batch --masks and --aa (and the manifest's per-job "masks" and "aa") write what render
--masks and --aa write for the same job."""

import json

import pytest

from conftest import cli_error, run_cli
from gltf_scene import QuadScene

W, H = 32, 24
MASK_SUFFIXES = (".instances.png", ".semantic.png", ".masks.json")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    scene = QuadScene(W, H)
    scene.add_quad(2, 2, 12, 10, node="table", cls="furniture")
    scene.add_quad(8, 6, 16, 14, z=1.0, node="cup")
    # A slanted edge, so that anti-aliasing changes the beauty.
    scene.add_corners([(2, -10, 0), (14, -9, 0), (10, 0, 0), (3, -1, 0)], node="ramp")
    path = tmp_path_factory.mktemp("batch_options") / "scenes"
    path.mkdir()
    scene.write(path / "quads.gltf")
    return path


def render(binary, folder, tmp_path, stem, *args):
    """render with the batch's size; returns the stem the files were written to."""
    status, _, stderr = run_cli(binary, "render", folder / "quads.gltf", "--width", W,
                                "--height", H, "-o", tmp_path / f"{stem}.png", *args)
    assert status == 0, stderr
    return tmp_path / stem


def same_bytes(a, b):
    return a.read_bytes() == b.read_bytes()


def test_batch_masks_and_aa_equal_render(binary, folder, tmp_path):
    status, _, stderr = run_cli(binary, "batch", folder, "--out", tmp_path / "out", "--width", W,
                                "--height", H, "--masks", "--aa", 4, "-q")
    assert status == 0, stderr
    expected = render(binary, folder, tmp_path, "r", "--masks", tmp_path / "r", "--aa", 4)
    plain = render(binary, folder, tmp_path, "plain")
    out = tmp_path / "out" / "quads"
    assert same_bytes(out.with_suffix(".png"), expected.with_suffix(".png"))
    assert not same_bytes(expected.with_suffix(".png"), plain.with_suffix(".png"))
    for suffix in MASK_SUFFIXES:
        assert same_bytes(tmp_path / "out" / f"quads{suffix}", tmp_path / f"r{suffix}"), suffix


def test_manifest_jobs_take_their_own_masks_and_aa(binary, folder, tmp_path):
    manifest = folder / "jobs.json"
    manifest.write_text(json.dumps({"jobs": [
        {"scene": "quads.gltf", "outputs": ["a/one.png"], "masks": "a/one", "aa": 8},
        {"scene": "quads.gltf", "outputs": ["b/two.png"]},
    ]}))
    status, _, stderr = run_cli(binary, "batch", manifest, "--out", tmp_path / "out",
                                "--width", W, "--height", H, "-q",
                                "--report", tmp_path / "report.json")
    assert status == 0, stderr
    one = render(binary, folder, tmp_path, "one", "--masks", tmp_path / "one", "--aa", 8)
    two = render(binary, folder, tmp_path, "two")
    assert same_bytes(tmp_path / "out" / "a" / "one.png", one.with_suffix(".png"))
    for suffix in MASK_SUFFIXES:
        assert same_bytes(tmp_path / "out" / "a" / f"one{suffix}", tmp_path / f"one{suffix}")
    assert same_bytes(tmp_path / "out" / "b" / "two.png", two.with_suffix(".png"))
    assert sorted(p.name for p in (tmp_path / "out" / "b").iterdir()) == ["two.png"]
    report = json.loads((tmp_path / "report.json").read_text())
    written = {p.replace("\\", "/").split("/out/")[-1] for p in report["jobs"][0]["outputs"]}
    assert written == {"a/one.png"} | {f"a/one{suffix}" for suffix in MASK_SUFFIXES}


def test_masks_alone_are_enough_to_write(binary, folder, tmp_path):
    status, _, stderr = run_cli(binary, "batch", folder / "quads.gltf", "--out", tmp_path / "out",
                                "--width", W, "--height", H, "--no-png", "--masks", "-q")
    assert status == 0, stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == sorted(
        f"quads{suffix}" for suffix in MASK_SUFFIXES)


@pytest.mark.parametrize("job, message", [
    ({"aa": 3}, "jobs[0].aa: expected 1, 4, 8 or 16"),
    ({"aa": 2.5}, "jobs[0].aa: expected an integer in [1, 16]"),
    ({"aa": 32}, "jobs[0].aa: expected an integer in [1, 16]"),
    ({"masks": "../m"}, 'jobs[0].masks: "../m": ".." would leave the output folder; output names are '
                        'relative to --out'),
    ({"masks": ""}, "jobs[0].masks: expected a non-empty string"),
])
def test_bad_manifest_masks_or_aa_fail_before_anything_renders(binary, folder, tmp_path, job,
                                                                message):
    manifest = tmp_path / "jobs.json"
    manifest.write_text(json.dumps({"jobs": [{"scene": str(folder / "quads.gltf"), **job}]}))
    error = cli_error(binary, "batch", manifest, "--out", tmp_path / "out", "--width", W,
                      "--height", H)
    assert error == f"{manifest}: {message}"
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_batch_aa_takes_the_render_values(binary, folder, tmp_path):
    status, _, stderr = run_cli(binary, "batch", folder, "--out", tmp_path / "out", "--aa", 3)
    assert status == 2 and "--aa" in stderr, stderr
    assert not (tmp_path / "out").exists()
