"""omnishadow.keep_shader_cache(): Mesa's shader cache kept where Mesa's own place cannot be
written (cli/shader_cache_folder.h). It sets the process's environment, so each check runs in a
child interpreter."""

import json
import os
import subprocess
import sys

from conftest import DEMO_LIGHTS, DEMO_SCENE

CHILD = r"""
import json, sys
import omnishadow
keep = sys.argv[3] == "1"
result = {}
if keep:
    result["first"] = omnishadow.keep_shader_cache()
    result["second"] = omnishadow.keep_shader_cache()
renderer = omnishadow.Renderer()
renderer.render(omnishadow.load_scene(sys.argv[1]), omnishadow.load_lights(sys.argv[2]),
                width=32, height=32).beauty
print(json.dumps(result))
"""

MESA_VARIABLES = ("MESA_SHADER_CACHE_DIR", "MESA_GLSL_CACHE_DIR", "MESA_SHADER_CACHE_DISABLE",
                  "MESA_GLSL_CACHE_DISABLE")


def run_child(tmp_path, keep, extra_env=None):
    (tmp_path / "file").write_text("not a folder")
    (tmp_path / "tmp").mkdir(exist_ok=True)
    env = {k: v for k, v in os.environ.items() if k not in MESA_VARIABLES}
    env.update(XDG_CACHE_HOME=str(tmp_path / "file" / "cache"), TMPDIR=str(tmp_path / "tmp"),
               **(extra_env or {}))
    done = subprocess.run([sys.executable, "-c", CHILD, str(DEMO_SCENE), str(DEMO_LIGHTS),
                           "1" if keep else "0"], capture_output=True, text=True, env=env,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1]), done.stderr


def test_keep_shader_cache_gives_mesa_a_folder_where_its_own_cannot_be_written(tmp_path):
    result, stderr = run_child(tmp_path, keep=True)
    folder = tmp_path / "tmp" / f"omnishadow-shader-cache-{os.getuid()}" / "mesa_shader_cache"
    assert result["first"]["source"] == "fallback", result
    assert result["first"]["folder"] == str(folder), result
    assert result["second"] == result["first"], result
    assert (folder / "index").is_file(), stderr
    assert len(list(folder.rglob("*"))) > 2, "the index and no shader"
    assert "disabling" not in stderr, stderr


def test_without_the_call_the_module_leaves_the_environment_alone(tmp_path):
    result, stderr = run_child(tmp_path, keep=False)
    assert result == {}
    assert not any((tmp_path / "tmp").iterdir())
    # Mesa's own message: it keeps nothing where XDG_CACHE_HOME cannot be made.
    assert "disabling" in stderr, stderr


def test_mesas_own_variables_are_left_alone(tmp_path):
    result, _ = run_child(tmp_path, keep=True, extra_env={"MESA_SHADER_CACHE_DISABLE": "true"})
    assert result["first"] == {"source": "users_choice", "folder": "",
                               "description": result["first"]["description"]}, result
    assert not any((tmp_path / "tmp").iterdir())
