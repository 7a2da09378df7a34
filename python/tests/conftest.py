"""Shared fixtures: the module (PYTHONPATH=build/python, set by CTest), the CLI binary, one
Renderer per test session (made on the main thread) and the repository's scenes."""

import json
import os
import subprocess
from pathlib import Path

import pytest

import omnishadow

SOURCE_DIR = Path(__file__).resolve().parents[2]
DEMO_SCENE = SOURCE_DIR / "scenes" / "demo" / "room.gltf"
DEMO_LIGHTS = SOURCE_DIR / "scenes" / "demo" / "room.lights.json"


@pytest.fixture(scope="session")
def binary():
    path = os.environ.get("OMNISHADOW_BINARY", str(SOURCE_DIR / "build" / "omnishadow"))
    if not Path(path).exists():
        pytest.fail(f"{path}: the omnishadow binary is not built (set OMNISHADOW_BINARY)")
    return path


@pytest.fixture(scope="session")
def renderer():
    return omnishadow.Renderer()


@pytest.fixture(scope="session")
def demo_scene():
    return omnishadow.load_scene(DEMO_SCENE)


def run_cli(binary, *args):
    """Runs the CLI; returns (exit status, stdout, stderr)."""
    done = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


def cli_render_demo(binary, setup, tmp_path, width, height):
    """The demo scene rendered by the CLI with the lights file `setup` (a dict) at width x
    height, which must succeed: its PNG as read_image() gives it, (pixels, channel names)."""
    lights_path = tmp_path / "lights.json"
    lights_path.write_text(json.dumps(setup))
    status, _, stderr = run_cli(binary, "render", DEMO_SCENE, "-l", lights_path, "--width", width,
                                "--height", height, "-o", tmp_path / "cli.png")
    assert status == 0, stderr
    return omnishadow.read_image(tmp_path / "cli.png")


def cli_error(binary, *args):
    """The one-line message of a CLI run that must fail with status 2, without 'omnishadow: '."""
    status, _, stderr = run_cli(binary, *args)
    assert status == 2, stderr
    lines = [line for line in stderr.splitlines() if not line.startswith("omnishadow: warning:")]
    assert len(lines) == 1, stderr
    assert lines[0].startswith("omnishadow: ")
    return lines[0][len("omnishadow: "):]
