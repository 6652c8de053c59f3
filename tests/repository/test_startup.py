"""A mistyped name is answered before anything heavy is imported: the registry loads every
plugin, but the plugins import the simulator, the recorder and the geometry libraries
only where they are used, and the commands look their names up before they import the
machinery that runs them. (How fast that is: benchmarks/startup.py.)"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

# Each takes from 0.1 s (matplotlib) to 0.4 s (rerun) to import.
HEAVY = (
    "coal", "matplotlib", "moderngl", "pinocchio", "placo", "rerun", "sapien", "scipy",
    "trimesh",
)  # fmt: skip
DEMO_IMAGE = Path(__file__).parents[2] / "graspframe" / "run" / "demo" / "demo.png"

# The command in a fresh process: its exit code, its error and the heavy modules loaded.
SCRIPT = f"""
import contextlib, io, json, sys
from graspframe.cli.commands import main
error = io.StringIO()
with contextlib.redirect_stderr(error):
    code = main(sys.argv[1:])
heavy = sorted(name for name in {HEAVY!r} if name in sys.modules)
print(json.dumps({{"code": code, "error": error.getvalue(), "heavy": heavy}}))
"""


def _run_fresh(command: list[str]) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT, *command],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    return json.loads(done.stdout.splitlines()[-1])


@pytest.mark.parametrize(
    ("command", "message"),
    [
        (["run", "--hand", "barret"], "unknown hand 'barret'; known hands: barrett, human"),
        (["run", "--arm", "kukka"], "unknown arm 'kukka'; known arms: kuka"),
        (["run", "--grasp", "pinch", "--object", "bal"], "unknown object 'bal'"),
        (["run", "--backend", "mujoco"], "unknown backend 'mujoco'; known backends: sapien"),
        (["check-hand", "barret"], "unknown hand 'barret'"),
        (["evaluate", "--hands", "barret"], "unknown hand 'barret'"),
        (["classify", "--classifier", "hog", str(DEMO_IMAGE)], "unknown classifier 'hog'"),
    ],
)
def test_an_unknown_name_is_answered_without_heavy_imports(command, message):
    answer = _run_fresh(command)
    assert answer["code"] == 1
    assert message in " ".join(answer["error"].split())
    assert answer["heavy"] == []
