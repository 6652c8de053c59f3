"""The wheel carries the core, every built-in plugin and every model file, and a
non-editable install finds them all without the source tree."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[2]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--quiet",
            "--no-deps",
            "--no-build-isolation",
            "--wheel-dir",
            str(out),
            str(ROOT),
        ],
        check=True,
        capture_output=True,
    )
    (path,) = out.glob("graspframe-*.whl")
    return path


def _builtin_plugin_modules() -> dict[str, str]:
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    return project["entry-points"]["graspframe"]


@pytest.mark.slow
def test_wheel_contains_models_and_plugins(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for urdf in ROOT.glob("robots/**/*.urdf"):
        member = "graspframe_robots/" + urdf.relative_to(ROOT / "robots").as_posix()
        assert member in names, f"{member} is missing from the wheel"
    for module in _builtin_plugin_modules().values():
        member = module.replace(".", "/") + ".py"
        assert member in names, f"plugin module {member} is missing from the wheel"
    assert "graspframe/py.typed" in names, "the PEP 561 marker is missing from the wheel"


@pytest.mark.slow
def test_installed_wheel_finds_every_model_file(wheel, tmp_path):
    site = tmp_path / "site"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--no-deps",
            "--target",
            str(site),
            str(wheel),
        ],
        check=True,
        capture_output=True,
    )
    # The models of the hands and arms the graspframe distribution provides; plugins of
    # other installed distributions (a plugin author's own, installed editable) are theirs.
    probe = (
        "import json; from graspframe.plugin_system.registry import default_registry as r; "
        "reg = r(); "
        "print(json.dumps({'plugins': {p.name: [p.status, p.error] for p in reg.plugins}, "
        "'models': [str(e.item.model_path) for k in ('hand', 'arm') for n in reg.names(k) "
        "for e in [reg.entry(k, n)] if e.package == 'graspframe']}))"
    )
    env = dict(os.environ, PYTHONPATH=str(site))
    result = subprocess.run(
        [sys.executable, "-c", probe],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
        check=True,
    )
    report = json.loads(result.stdout)
    for name in _builtin_plugin_modules():
        assert report["plugins"][name][0] == "loaded", report["plugins"][name]
    assert report["models"], "no hand or arm registered"
    for model in report["models"]:
        assert Path(model).is_file()
        assert Path(model).is_relative_to(site), f"{model} resolved outside the installed wheel"
