"""Checks every registered robot model must pass, one test item per robot (ids = names).

- its plugin registers exactly that robot;
- the generator in tools/robot_models reproduces its shipped URDF (built-in robots, and
  the floating base that carries a free hand);
- SAPIEN loads the URDF with the joints, limits and links the URDF declares (an arm's
  joints in the order of Pinocchio and of its description); an arm at its home pose
  does not penetrate itself.

The contract checks run per robot in test_registered_contracts.py. What is specific to
one robot (its dimensions, preshapes, kinematics) stays in tests/test_robot_<name>.py.
"""

from __future__ import annotations

import importlib
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.plugin_system.registry import Registry, default_registry
from graspframe.robot_models.floating_base import floating_base
from graspframe.robot_models.model import model_of, summarize_urdf

ROOT = Path(__file__).parents[2]
BUILT_IN_PACKAGE = "graspframe"
REGISTRY = default_registry()
HANDS = REGISTRY.names("hand")
ARMS = REGISTRY.names("arm")
ROBOTS = [*HANDS, *ARMS]
BUILT_IN_ROBOTS = [
    entry.name
    for kind in ("hand", "arm")
    for entry in REGISTRY.entries(kind)
    if entry.package == BUILT_IN_PACKAGE
]
SAPIEN_LIMIT_TOL = 1e-5  # [rad] SAPIEN keeps joint limits in float32 (~1e-7 relative)


def kind_of(name: str) -> str:
    return "hand" if name in HANDS else "arm"


def robot(name: str) -> HandDescription | ArmDescription:
    """The registered hand or arm called `name`."""
    return REGISTRY.get_hand(name) if name in HANDS else REGISTRY.get_arm(name)


def shipped_model(name: str) -> Path:
    """The URDF the wheel ships for a built-in robot or the floating base."""
    return floating_base().model_path if name == "floating_base" else robot(name).model_path


def sapien_articulation(model_path: Path):
    """(scene, articulation) of a URDF loaded with its root fixed."""
    sapien = pytest.importorskip("sapien")
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    return scene, loader.load(str(model_path))


@pytest.mark.parametrize("name", ROBOTS)
def test_plugin_registers_exactly_its_robot(name):
    kind = kind_of(name)
    entry = REGISTRY.entry(kind, name)
    plugin = next(p for p in REGISTRY.plugins if p.name == entry.plugin)
    registry = Registry(strict=True)
    info = registry.add_plugin(entry.plugin, importlib.import_module(plugin.module))
    assert [provided for provided in info.provides if provided[0] == kind] == [(kind, name)]
    assert registry.entry(kind, name).item == robot(name)


@pytest.mark.parametrize("name", [*BUILT_IN_ROBOTS, "floating_base"])
def test_generator_reproduces_the_shipped_urdf(name, tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT))  # tools/ is a source-tree folder, not installed
    generator = importlib.import_module(f"tools.robot_models.{name}")
    written = generator.build().write(tmp_path / f"{name}.urdf")
    assert written.read_text() == shipped_model(name).read_text(), (
        f"the shipped {name}.urdf is stale: run python -m tools.robot_models.{name}"
    )


@pytest.mark.parametrize("name", ROBOTS)
def test_sapien_loads_the_joints_limits_and_links_of_the_urdf(name):
    description = robot(name)
    _, articulation = sapien_articulation(description.model_path)
    urdf = summarize_urdf(model_of(description))

    names = [joint.name for joint in articulation.get_active_joints()]
    assert set(names) == set(urdf.joints)
    for joint_name, limits in zip(names, articulation.get_qlimits(), strict=True):
        joint = urdf.joints[joint_name]
        assert tuple(limits) == pytest.approx((joint.lower, joint.upper), abs=SAPIEN_LIMIT_TOL)

    links = {link.name for link in articulation.get_links()}
    assert urdf.links <= links
    if isinstance(description, HandDescription):
        assert set(description.finger_of_link()) <= links
        assert description.palm_frame in links
    else:
        # A serial chain: SAPIEN, Pinocchio and the description list the joints alike.
        model = pin.buildModelFromUrdf(str(description.model_path), False)
        pinocchio_names = [model.names[i] for i in range(1, model.njoints)]
        assert names == pinocchio_names == list(description.joint_names)


@pytest.mark.parametrize("name", ARMS)
def test_sapien_arm_does_not_penetrate_itself_at_home(name):
    arm = REGISTRY.get_arm(name)
    scene, articulation = sapien_articulation(arm.model_path)
    articulation.set_qpos(np.asarray(arm.home_q))
    scene.step()
    depths = [point.separation for contact in scene.get_contacts() for point in contact.points]
    assert all(depth >= 0.0 for depth in depths), depths
