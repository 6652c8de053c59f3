"""Third-party plugin distributions, built and installed for real with pip."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from fakes import FAKE_HAND_URDF

PLUGIN_CODE = """
import math
from pathlib import Path

from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.hal import DriveGains, HandDescription, HandPreshape, JointSpec
from graspframe.plugin_system import hookimpl

HERE = Path(__file__).parent
JOINTS = (
    JointSpec("fk_finger_joint", 0.0, 1.5, max_velocity=2.0, max_effort=2.0),
    JointSpec("fk_thumb_joint", 0.0, 1.5, max_velocity=2.0, max_effort=2.0),
)
PINCH = HandPreshape(
    "pinch",
    open_q={"fk_finger_joint": 0.1, "fk_thumb_joint": 0.1},
    closed_q={"fk_finger_joint": 1.2, "fk_thumb_joint": 1.2},
    delta=0.06,
)
TOY_HAND = HandDescription(
    name="toyhand",
    model_path=HERE / "toyhand.urdf",
    root_link="fk_base",
    joints=JOINTS,
    palm_frame="fk_palm_frame",
    palm_sensor_link="fk_base",
    real_fingers={PALM: ("fk_base",), "finger": ("fk_finger",), "thumb": ("fk_thumb",)},
    preshapes={"pinch": PINCH},
    grasp_map={g: "pinch" for g in HumanGrasp},
    drive=DriveGains(stiffness=5.0, damping=0.5, force_limit=1.0),
)


@hookimpl
def graspframe_register_hands(register):
    register(TOY_HAND)
"""

PYPROJECT = """
[build-system]
requires = ["setuptools>=64"]
build-backend = "setuptools.build_meta"

[project]
name = "{dist}"
version = "0.0.1"

[project.entry-points.graspframe]
{entry} = "{package}.plugin"

[tool.setuptools]
packages = ["{package}"]

[tool.setuptools.package-data]
{package} = ["*.urdf"]
"""


def _build_and_install(tmp_path: Path, dist: str, entry: str, plugin_code: str) -> Path:
    package = dist.replace("-", "_")
    src = tmp_path / f"{dist}-src"
    (src / package).mkdir(parents=True)
    (src / "pyproject.toml").write_text(PYPROJECT.format(dist=dist, entry=entry, package=package))
    (src / package / "__init__.py").write_text("")
    (src / package / "plugin.py").write_text(textwrap.dedent(plugin_code))
    (src / package / "toyhand.urdf").write_text(FAKE_HAND_URDF)
    target = tmp_path / "site"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--no-deps",
            "--no-build-isolation",
            "--target",
            str(target),
            str(src),
        ],
        check=True,
        capture_output=True,
    )
    return target


def _graspframe(args: list[str], site: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(site), COLUMNS="200")
    env.pop("GRASPFRAME_STRICT_PLUGINS", None)
    return subprocess.run(
        [sys.executable, "-m", "graspframe.cli.commands", *args],
        capture_output=True,
        text=True,
        env=env,
        cwd=site,
    )


@pytest.mark.slow
def test_installed_third_party_hand_is_registered(tmp_path):
    site = _build_and_install(tmp_path, "graspframe-toyhand", "toyhand", PLUGIN_CODE)
    result = _graspframe(["plugins", "--json"], site)
    assert result.returncode == 0, result.stderr
    rows = {row["plugin"]: row for row in json.loads(result.stdout)}
    toy = rows["toyhand"]
    assert toy["status"] == "loaded", toy["error"]
    assert toy["package"] == "graspframe-toyhand"
    assert toy["version"] == "0.0.1"
    assert toy["provides"] == [{"kind": "hand", "name": "toyhand"}]


@pytest.mark.slow
def test_plugin_that_raises_on_import_does_not_take_the_cli_down(tmp_path):
    broken = "raise RuntimeError('this plugin is broken on purpose')\n"
    site = _build_and_install(tmp_path, "graspframe-broken", "broken", broken)

    help_result = _graspframe(["--help"], site)
    assert help_result.returncode == 0, help_result.stderr
    assert "plugins" in help_result.stdout

    table = _graspframe(["plugins"], site)
    assert table.returncode == 0, table.stderr
    assert "broken" in table.stdout and "failed" in table.stdout
    assert "this plugin is broken on purpose" in table.stdout

    rows = {
        row["plugin"]: row for row in json.loads(_graspframe(["plugins", "--json"], site).stdout)
    }
    assert rows["broken"]["status"] == "failed"
    assert "RuntimeError: this plugin is broken on purpose" in rows["broken"]["error"]
    # The other plugins are unaffected.
    assert all(r["status"] == "loaded" for name, r in rows.items() if name != "broken")
