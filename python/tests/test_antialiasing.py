"""--aa N smooths the beauty; AOVs, ids, masks and depth stay those of the pixel centers."""

import numpy as np
import pytest

import omnishadow
from conftest import run_cli
from gltf_scene import QuadScene

W, H = 16, 12


@pytest.fixture(scope="module")
def edge_scene(tmp_path_factory):
    # The quad's right edge is a quarter into column 10: the center of column 10 is outside,
    # and a quarter of each sample pattern (4, 8 and 16 samples) falls inside.
    scene = QuadScene(W, H)
    scene.add_quad(2, 2, 10.25, 10, node="quad")
    return omnishadow.load_scene(scene.write(tmp_path_factory.mktemp("aa") / "edge.gltf"))


@pytest.mark.parametrize("samples", [4, 8, 16])
def test_beauty_is_antialiased_and_aovs_stay_exact(renderer, edge_scene, samples):
    exact = renderer.render(edge_scene, width=W, height=H, aovs=["all"], masks=True)
    smooth = renderer.render(edge_scene, width=W, height=H, aovs=["all"], masks=True, aa=samples)
    alpha = smooth.beauty[:, :, 3]
    np.testing.assert_array_equal(exact.beauty[3:9, 10, 3], 0.0)
    np.testing.assert_array_equal(alpha[3:9, 10], 0.25)
    np.testing.assert_array_equal(alpha[3:9, 3:10], 1.0)
    np.testing.assert_array_equal(alpha[:, 12:], 0.0)
    for name in exact.channels:
        if name not in "RGBA":
            np.testing.assert_array_equal(smooth[name], exact[name], err_msg=name)
    np.testing.assert_array_equal(smooth.object_id[3:9, 10], -1)
    np.testing.assert_array_equal(smooth.masks["instances"], exact.masks["instances"])
    assert smooth.masks["index"] == exact.masks["index"]


def test_cli_aa_matches_python(binary, renderer, edge_scene, tmp_path):
    status, _, stderr = run_cli(binary, "render", edge_scene.path, "--width", W, "--height", H,
                                "--aa", 4, "-o", tmp_path / "cli.png")
    assert status == 0, stderr
    frame = renderer.render(edge_scene, width=W, height=H, aa=4)
    frame.save(tmp_path / "py.png")
    assert (tmp_path / "cli.png").read_bytes() == (tmp_path / "py.png").read_bytes()


def test_unknown_sample_count_is_refused(binary, renderer, edge_scene, tmp_path):
    with pytest.raises(omnishadow.InputError, match=r"^--aa 3: expected 1, 4, 8 or 16$"):
        renderer.render(edge_scene, width=W, height=H, aa=3)
    status, _, stderr = run_cli(binary, "render", edge_scene.path, "--aa", 3,
                                "-o", tmp_path / "out.png")
    assert status == 2 and "--aa" in stderr
    assert not (tmp_path / "out.png").exists()
