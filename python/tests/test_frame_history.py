"""A frame does not depend on what its Renderer drew before: seeded sequences of frames over the
real models in scenes/ (sizes repeated and changed; AOVs, masks with and without a picture,
anti-aliasing, shadow map readback, Phong, moved cameras, mixed) each equal, array for array,
the same frame from a fresh Renderer. The renderer keeps targets, shadow maps, programs,
textures and geometry from frame to frame; whatever it keeps must not show."""

import random

import numpy as np
import pytest

import omnishadow
from conftest import SOURCE_DIR

MODELS = sorted(p for folder in ("thirdparty", "khronos")
                for p in (SOURCE_DIR / "scenes" / folder).rglob("*")
                if p.suffix in (".gltf", ".glb"))


def random_frame(rng):
    kw = {"width": rng.choice([64, 64, 48, 80]), "height": rng.choice([48, 48, 40])}
    if rng.random() < 0.3:
        kw["aovs"] = rng.choice([[], ["albedo"], ["normal", "depth"], ["visibility"]])
    if rng.random() < 0.4:
        kw["masks"] = True
        kw["beauty"] = rng.random() < 0.6
    if rng.random() < 0.15:
        kw["aa"] = 4
    if rng.random() < 0.15:
        kw["shadow_maps"] = True
    if rng.random() < 0.2:
        kw["shading"] = "phong"
    if rng.random() < 0.2:
        kw["camera"] = {"eye": [rng.uniform(-3, 3), rng.uniform(0.5, 3), rng.uniform(-3, 3)]}
    return kw


def contents(frame, kw):
    """Everything the frame holds, as plain values and arrays (an error as its text)."""
    out = {"channels": {c: frame[c] for c in frame.channels}}
    if kw.get("beauty", True):
        out["beauty"] = frame.beauty
    if kw.get("masks"):
        out["masks"] = frame.masks
    if kw.get("shadow_maps"):
        out["shadow_maps"] = frame.shadow_maps
    return out


def draw(renderer, scene, kw):
    try:
        return contents(renderer.render(scene, **kw), kw)
    except (omnishadow.InputError, omnishadow.RenderError) as error:
        return f"{type(error).__name__}: {error}"


def first_difference(x, y, where="frame"):
    """None when x and y are equal, else where they first differ."""
    if isinstance(x, np.ndarray):
        same = isinstance(y, np.ndarray) and x.shape == y.shape and \
            np.array_equal(x, y, equal_nan=True)
        return None if same else where
    if isinstance(x, dict):
        if not isinstance(y, dict) or x.keys() != y.keys():
            return where + " (keys)"
        return next((d for k in x if (d := first_difference(x[k], y[k], f"{where}.{k}"))), None)
    if isinstance(x, (list, tuple)):
        if not isinstance(y, (list, tuple)) or len(x) != len(y):
            return where + " (length)"
        return next((d for i, (u, v) in enumerate(zip(x, y))
                     if (d := first_difference(u, v, f"{where}[{i}]"))), None)
    return None if x == y else where


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_frame_is_the_same_whatever_the_renderer_drew_before(seed):
    assert len(MODELS) >= 10, MODELS
    rng = random.Random(seed)
    scenes = {}
    kept = omnishadow.Renderer()
    for index in range(30):
        path = rng.choice(MODELS)
        kw = random_frame(rng)
        if path not in scenes:
            scenes[path] = omnishadow.load_scene(path)
        scene = scenes[path]
        after_others = draw(kept, scene, kw)
        alone = draw(omnishadow.Renderer(), scene, kw)
        difference = first_difference(after_others, alone)
        errors = [r for r in (after_others, alone) if isinstance(r, str)]
        assert difference is None, f"frame {index}, {path.name}, {kw}: {difference} {errors}"
