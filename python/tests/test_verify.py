"""Renderer.verify() gives the agreement table of `omnishadow verify --json` as Python data."""

import json

import pytest

import omnishadow
from conftest import DEMO_LIGHTS, DEMO_SCENE, run_cli


def test_verify_table_equals_the_cli(binary, renderer, demo_scene):
    status, stdout, stderr = run_cli(binary, "verify", DEMO_SCENE, "-l", DEMO_LIGHTS, "--width",
                                     48, "--height", 32, "--json", "--max-error", "0.5")
    assert status == 0, stderr
    cli = json.loads(stdout)
    table = renderer.verify(demo_scene, DEMO_LIGHTS, width=48, height=32, max_error=0.005)
    assert (table["width"], table["height"], table["camera"]) == (48, 32, cli["camera"])
    assert [light["name"] for light in table["lights"]] == ["warm", "cool"]
    for ours, theirs in zip(table["lights"], cli["lights"]):
        for key in ("name", "type", "shadowed", "filter", "resolution", "skipped"):
            assert ours[key] == theirs[key], key
        for group in ("interior", "edge"):
            for key, value in theirs[group].items():
                assert ours[group][key] == pytest.approx(value), (group, key)
        assert ours["interior"]["evaluated"] > 0
    only = renderer.verify(demo_scene, DEMO_LIGHTS, light="cool", width=48, height=32)
    assert [light["name"] for light in only["lights"]] == ["cool"]
    assert only["lights"][0]["interior"] == table["lights"][1]["interior"]


def test_verify_errors(renderer, demo_scene):
    with pytest.raises(omnishadow.InputError, match='no such light .*"warm", "cool"'):
        renderer.verify(demo_scene, DEMO_LIGHTS, light="sun", width=8, height=8)
    with pytest.raises(omnishadow.InputError, match="expected a square number"):
        renderer.verify(demo_scene, DEMO_LIGHTS, source_samples=10, width=8, height=8)
