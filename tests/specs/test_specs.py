"""Hand and arm specs (graspframe/specs/): the worked examples on the real vendor files,
every kind of bad spec refused in one line, and specs wherever a name is accepted."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import pytest
from conftest import LEAP_HAND_SPEC, PANDA_SPEC

from graspframe.checks.self_collision import signed_link_distance
from graspframe.cli.commands import main
from graspframe.common.errors import DescriptionError, PluginError
from graspframe.common.grasps import HumanGrasp
from graspframe.hal import ArmDescription, HandDescription
from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.registry import Registry, default_registry
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.specs import load_spec
from graspframe.testing import arm_problems, hand_problems, self_collision_problems


def test_the_leap_hand_spec_describes_the_vendor_hand(leap_hand_dir):
    hand = load_spec(LEAP_HAND_SPEC)
    assert isinstance(hand, HandDescription)
    assert hand.model_path == leap_hand_dir / "leap_hand_right.urdf"
    assert len(hand.joints) == 16 and {j.max_velocity for j in hand.joints} == {2.0}
    assert {j.max_effort for j in hand.joints} == {0.95}  # from the URDF
    assert set(hand.grasp_map) == set(HumanGrasp)
    assert {"leap_palm", "leap_palm_pad"} <= model_of(hand).link_names
    # No preshape states a delta: each comes from the fingertip frames, open preshape.
    assert all(0.05 < p.delta < 0.2 for p in hand.preshapes.values())
    assert hand_problems(hand) == []


# The spec's palm pad stops short of the thumb's root and the pinch's index and middle
# sit side by side; the simulator runs without self-collision, so no grasp would show an
# overlap.
def test_the_leap_hand_spec_opens_free_of_self_collision(leap_hand_dir):
    assert self_collision_problems(load_spec(LEAP_HAND_SPEC)) == []


def test_the_leap_pinch_keeps_index_and_middle_apart_open_and_closed(leap_hand_dir):
    hand = load_spec(LEAP_HAND_SPEC)
    assert isinstance(hand, HandDescription)
    model = CollisionModel(model_of(hand))
    pinch = hand.preshapes["pinch"]
    for q in (pinch.open_q, pinch.closed_q):
        model.place(hand.with_model_followers(q))
        gap = min(
            signed_link_distance(model, index_link, middle_link)
            for index_link in ("pip", "dip", "fingertip")
            for middle_link in ("pip_2", "dip_2", "fingertip_2")
        )
        assert gap > 0.001  # [m] side by side, not through each other


def test_the_panda_spec_describes_the_vendor_arm(panda_description_dir):
    arm = load_spec(PANDA_SPEC)
    assert isinstance(arm, ArmDescription)
    assert arm.joint_names == tuple(f"panda_joint{i}" for i in range(1, 8))
    assert [j.max_acceleration for j in arm.joints] == [15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0]
    assert arm.joints[0].max_velocity == pytest.approx(2.175)  # from the URDF
    assert arm.home_q[3] == pytest.approx(math.radians(-135.0))
    assert "panda_hand" not in model_of(arm).link_names  # the vendor's gripper is dropped
    assert arm_problems(arm) == []


HAND_SPEC = """\
kind = "hand"
name = "toy"
urdf = "toy.urdf"
root_link = "base"
palm_frame = "palm"
palm_sensor_link = "palm"
{extra_top}
[frames.palm]
parent = "base"
xyz = [0.0, 0.0, 0.05]
[fingers]
finger = ["finger"]
palm = ["base", "palm"]
[drive]
stiffness = 2.0
damping = 0.1
force_limit = 1.0
[preshapes.close]
delta = 0.08
[preshapes.close.open_deg]
finger_joint = 0.0
[preshapes.close.closed_deg]
finger_joint = 80.0
{extra}
[grasp_map]
large_diameter = "close"
small_diameter = "close"
abducted_thumb = "close"
pinch = "close"
power_sphere = "close"
precision_disc = "close"
"""

TOY_URDF = """<?xml version="1.0"?>
<robot name="toy">
  <link name="base">
    <collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision>
  </link>
  <link name="finger">
    <collision><geometry><box size="0.01 0.01 0.05"/></geometry></collision>
  </link>
  <joint name="finger_joint" type="revolute"><parent link="base"/><child link="finger"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="1.6" effort="1" velocity="2"/></joint>
</robot>
"""


def _spec(tmp_path: Path, extra: str = "", extra_top: str = "", text: str | None = None) -> Path:
    (tmp_path / "toy.urdf").write_text(TOY_URDF)
    path = tmp_path / "toy.toml"
    path.write_text(
        text if text is not None else HAND_SPEC.format(extra=extra, extra_top=extra_top)
    )
    return path


def test_a_small_spec_loads(tmp_path):
    hand = load_spec(_spec(tmp_path))
    assert hand.joint_names == ("finger_joint",)
    assert hand.preshape("close").closed_q["finger_joint"] == pytest.approx(math.radians(80))


def test_a_spec_says_whether_its_controller_moves_the_joints_together(tmp_path):
    assert not load_spec(_spec(tmp_path)).synchronised_closing
    text = HAND_SPEC.format(extra="", extra_top="")
    text = text.replace("[drive]", "[drive]\nsynchronised = true")
    assert load_spec(_spec(tmp_path, text=text)).synchronised_closing


@pytest.mark.parametrize(
    ("extra_top", "extra", "message"),
    [
        ("colour = 'red'", "", r"unknown key 'colour' in the spec; accepted: kind, name"),
        (
            "",
            "[preshapes.close.design]\nshape = 'sphere'",
            r"unknown key 'design' in \[preshapes.close\]",
        ),
        ("", "[joints]\nnames = ['elbow']", r"'elbow', which is not a movable joint of toy.urdf"),
        (
            "",
            "[joints]\nmax_velocity = [1.0, 2.0]",
            r"max_velocity \(one per joint\) must be a list of 1",
        ),
        ("", "[frames.tip]\nparent = 'finger'\nrpy = [0, 0, 0]\nrpy_deg = [0, 0, 0]", "not both"),
        (
            "",
            "[preshapes.wide]\ndelta = 0.1\n[preshapes.wide.open]\nfinger_joint = 0.0",
            "needs .closed. \\[rad\\] or .closed_deg.",
        ),
    ],
)
def test_a_bad_spec_is_refused_in_one_line(tmp_path, extra_top, extra, message):
    with pytest.raises(DescriptionError, match=message) as info:
        load_spec(_spec(tmp_path, extra=extra, extra_top=extra_top))
    assert "\n" not in str(info.value) and str(info.value).startswith("spec toy.toml: ")


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda t: t.replace('kind = "hand"', 'kind = "gripper"'), "'kind' must be one of"),
        (lambda t: t.replace('urdf = "toy.urdf"', 'urdf = "${NO_SUCH_VARIABLE}/toy.urdf"'),
         "uses the environment variable NO_SUCH_VARIABLE, which is not set"),
        (lambda t: t.replace('pinch = "close"', 'pinch = "open"'), "'open', which is not a"),
        (lambda t: t.replace('palm = ["base", "palm"]', ""), "needs 'palm'"),
        (lambda t: t.replace("[drive]", "[drive\n"), "is not valid TOML"),
        (lambda t: t.replace("[drive]", "[drive]\nsynchronised = 'yes'"),
         r"\[drive\] synchronised must be true or false, got 'yes'"),
    ],
)  # fmt: skip
def test_more_bad_specs(tmp_path, edit, message):
    text = HAND_SPEC.format(extra="", extra_top="")
    with pytest.raises(DescriptionError, match=message):
        load_spec(_spec(tmp_path, text=edit(text)))


def test_an_arm_spec_needs_motion_limits(tmp_path):
    (tmp_path / "toy.urdf").write_text(TOY_URDF)
    path = tmp_path / "arm.toml"
    path.write_text(
        textwrap.dedent("""\
        kind = "arm"
        name = "toy_arm"
        urdf = "toy.urdf"
        base_link = "base"
        flange_link = "finger"
        home_q = [0.5]
        [drive]
        stiffness = 1.0
        damping = 0.1
        force_limit = 1.0
        """)
    )
    with pytest.raises(DescriptionError, match="joint 'finger_joint' needs max_acceleration"):
        load_spec(path)


def test_the_registry_takes_spec_paths_where_it_takes_names(tmp_path):
    path = _spec(tmp_path)
    registry = default_registry()
    assert registry.get_hand(str(path)).name == "toy"
    with pytest.raises(PluginError, match=r"describes a hand \(toy\), where arms are expected"):
        registry.get_arm(str(path))


def test_a_plugin_registers_a_spec_by_name(tmp_path):
    path = _spec(tmp_path)

    class SpecPlugin:
        @hookimpl
        def graspframe_register_hands(self, register):
            register(load_spec(path))

    registry = Registry(strict=True)
    registry.add_plugin("toy_plugin", SpecPlugin())
    assert registry.get_hand("toy").model_path == tmp_path / "toy.urdf"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["check-hand", "missing.toml"], "spec file not found"),
        (["run", "--hand", "{spec}", "--arm", "{spec}", "--grasp", "pinch"], "where arms are"),
    ],
)
def test_the_cli_refuses_bad_specs_in_one_line(tmp_path, capsys, argv, message):
    spec = _spec(tmp_path)
    argv = [a.format(spec=spec) for a in argv]
    assert main(argv) != 0
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
