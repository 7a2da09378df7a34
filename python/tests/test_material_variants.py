"""KHR_materials_variants from Python: load_scene(variant=...) draws the variant's materials,
as the CLI's --variant does, and refuses a variant the file lacks with the CLI's message."""

import json

import numpy as np
import pytest

import omnishadow
from gltf_scene import QuadScene

W, H = 16, 12


@pytest.fixture(scope="module")
def variants_scene(tmp_path_factory):
    scene = QuadScene(W, H)
    own = scene.material("own", color=(1, 1, 1, 1))
    red = scene.material("red", color=(1, 0, 0, 1))
    blue = scene.material("blue", color=(0, 0, 1, 1))
    scene.add_quad(0, 0, W, H, material=own)
    path = scene.write(tmp_path_factory.mktemp("variants") / "variants.gltf")
    gltf = json.loads(path.read_text())
    for m in gltf["materials"]:
        m["extensions"] = {"KHR_materials_unlit": {}}
    gltf["extensionsUsed"] = ["KHR_materials_unlit", "KHR_materials_variants"]
    gltf["extensions"] = {"KHR_materials_variants": {"variants": [{"name": "Red"}, {"name": "Blue"}]}}
    gltf["meshes"][0]["primitives"][0]["extensions"] = {"KHR_materials_variants": {"mappings": [
        {"material": red, "variants": [0]}, {"material": blue, "variants": [1]}]}}
    path.write_text(json.dumps(gltf))
    return path


@pytest.mark.parametrize("variant, rgb", [(None, (1, 1, 1)), ("Red", (1, 0, 0)), (1, (0, 0, 1))])
def test_variant_draws_its_materials(renderer, variants_scene, variant, rgb):
    scene = omnishadow.load_scene(variants_scene, variant=variant)
    assert scene.material_variants == ["Red", "Blue"]
    assert scene.material_variant == (None if variant is None else ["Red", "Blue"][0 if variant == "Red" else 1])
    frame = renderer.render(scene, width=W, height=H)
    beauty = np.asarray(frame.beauty)
    assert np.allclose(beauty[..., :3], np.array(rgb, np.float32), atol=1e-6)


def test_unknown_variant_raises_the_cli_message(binary, variants_scene):
    with pytest.raises(omnishadow.InputError) as error:
        omnishadow.load_scene(variants_scene, variant="Green")
    assert str(error.value) == (f"{variants_scene}: --variant Green: the file has no such material "
                                "variant (its variants: \"Red\", \"Blue\")")
    with pytest.raises(TypeError):
        omnishadow.load_scene(variants_scene, variant=1.5)
