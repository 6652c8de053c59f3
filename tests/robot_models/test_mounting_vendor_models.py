"""A hand mounted where it is bolted and an arm standing where its spec says, whatever
link their vendor's file is rooted at; a hand whose links overlap the arm's once mounted
refused in one line. Built at test time from the vendor files read in place: the LEAP
hand re-rooted at its palm (as a vendor rooted at the finger roots ships it), its mount
given as a link below the file's root or as a frame; the Kinova JACO2 as shipped."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from conftest import JACO2_SPEC, LEAP_HAND_SPEC, PANDA_SPEC, folder_state

from graspframe.cli.check_hand import check_hand_command
from graspframe.cli.commands import main
from graspframe.common.errors import DescriptionError
from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import R_from_rpy, inv_T, make_T, rpy_from_R
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.robot_models.mounting import MOUNT_OVERLAP_TOLERANCE, mount, mount_overlaps
from graspframe.run.request import RunRequest
from graspframe.run.runner import run_grasp
from graspframe.specs import load_spec

# The tests that load the JACO2 share one xdist worker: its links are decomposed once.
JACO2 = pytest.mark.xdist_group("jaco2")
MOUNT_FRAME = """mount_link = "leap_mount"
"""


def _leap_rooted_at_its_palm(leap_hand_dir: Path, folder: Path) -> Path:
    """The vendor's LEAP URDF rewritten with its root at `palm_lower` (the finger
    roots) and its wrist link `base` a fixed child 98 mm below: its one joint between
    the two turned round by hand, mesh names made absolute. Written in `folder`."""
    source = leap_hand_dir / "leap_hand_right.urdf"
    robot = ET.parse(source).getroot()
    for mesh in robot.iter("mesh"):
        mesh.set("filename", str(leap_hand_dir / mesh.get("filename", "")))
    joint = next(j for j in robot.iter("joint") if j.find("child").get("link") == "palm_lower")
    origin = joint.find("origin")
    xyz = [float(v) for v in origin.get("xyz").split()]
    rpy = [float(v) for v in origin.get("rpy").split()]
    T_palm_base = inv_T(make_T(R_from_rpy(*rpy), xyz))
    origin.set("xyz", " ".join(f"{v:.9g}" for v in T_palm_base[:3, 3]))
    origin.set("rpy", " ".join(f"{v:.9g}" for v in rpy_from_R(T_palm_base[:3, :3])))
    joint.find("parent").set("link", "palm_lower")
    joint.find("child").set("link", "base")
    path = folder / "leap_rooted_at_palm.urdf"
    path.write_text(ET.tostring(robot, encoding="unicode"))
    return path


def _leap_spec(folder: Path, urdf: Path, mount_lines: str) -> Path:
    """The LEAP example spec on another URDF, with its mount lines replaced."""
    text = LEAP_HAND_SPEC.read_text().replace("${LEAP_HAND_DIR}/leap_hand_right.urdf", str(urdf))
    text = text.replace('mount_link = "leap_mount"\n', mount_lines)
    path = folder / "leap_rerooted.toml"
    path.write_text(text)
    return path


def test_a_hand_rooted_at_its_fingers_is_mounted_at_its_wrist(leap_hand_dir, tmp_path):
    urdf = _leap_rooted_at_its_palm(leap_hand_dir, tmp_path)
    as_shipped = load_spec(LEAP_HAND_SPEC)
    # Mounted at the file's `base` link (now a child of the root) and at a frame below it.
    for mount_lines in ('mount_link = "base"\n', MOUNT_FRAME):
        rerooted = load_spec(_leap_spec(tmp_path, urdf, mount_lines))
        shipped_model, rerooted_model = (
            CollisionModel(model_of(as_shipped)),
            CollisionModel(model_of(rerooted)),
        )
        T_shift = np.eye(4)
        if mount_lines != MOUNT_FRAME:  # the shipped spec mounts 10 mm below `base`
            T_shift = shipped_model.T_root_frame("base")
        for frame in ("leap_palm", "thumb_tip_head", "index_tip_head", "palm_lower"):
            np.testing.assert_allclose(
                T_shift @ rerooted_model.T_root_frame(frame),
                shipped_model.T_root_frame(frame),
                atol=1e-9,
            )


def _sunk_leap_spec(leap_hand_dir: Path, folder: Path, dorsal: bool) -> Path:
    """The LEAP example with its mount frame 30 mm up the hand, inside the palm (the palm
    sinks into the arm), with or without its dorsal mounting."""
    spec = LEAP_HAND_SPEC.read_text().replace("xyz = [0.0, 0.0, -0.01]", "xyz = [0.0, 0.0, 0.03]")
    if not dorsal:
        spec = re.sub(r"\[mountings\.dorsal\].*?\nadapter = [^\n]*\n", "", spec, flags=re.S)
    path = folder / f"leap_sunk{'_dorsal' if dorsal else ''}.toml"
    path.write_text(spec.replace("${LEAP_HAND_DIR}", str(leap_hand_dir)))
    return path


def test_a_hand_mounted_inside_itself_is_refused_naming_links_and_depth(
    leap_hand_dir, tmp_path, capsys
):
    path = _sunk_leap_spec(leap_hand_dir, tmp_path, dorsal=False)
    hand = load_spec(path)
    robot_overlaps = mount_overlaps(mount(default_registry().get_arm("kuka"), hand, check=False))
    assert robot_overlaps and robot_overlaps[0].depth > 0.02
    with pytest.raises(DescriptionError) as error:
        mount(default_registry().get_arm("kuka"), hand)
    message = str(error.value)
    assert "\n" not in message and "palm_lower" in message and "kr5_link_6" in message
    assert "mm deep" in message
    # Refused before anything runs, by run, evaluate and check-hand alike.
    argv = ["run", "--hand", str(path), "--grasp", "pinch", "--no-record", "--out", str(tmp_path)]
    assert main(argv) == 1
    printed = " ".join(capsys.readouterr().err.split())
    assert "palm_lower' is" in printed and "mm deep in arm link 'kr5_link_6'" in printed
    argv = ["evaluate", "--hands", str(path), "--grasps", "pinch", "--directions", "0"]
    assert main([*argv, "--out", str(tmp_path / "sweep")]) == 1
    assert "mm deep in arm link 'kr5_link_6'" in " ".join(capsys.readouterr().err.split())
    assert not (tmp_path / "sweep" / "trials.jsonl").exists()
    assert check_hand_command(str(path), hold=False, arm="kuka") == 1
    report = capsys.readouterr().out
    assert "3. mounted on kuka: no hand link inside an arm link" in report
    assert "problem: bolted straight on: hand link 'palm_lower' is" in report


def test_a_mount_that_overlaps_the_arm_is_left_for_one_that_clears_it(leap_hand_dir, tmp_path):
    """The mounts are alternatives: the sunk LEAP hand with its dorsal plate is held by
    the plate; check-hand says the straight mount is not used, and passes the check."""
    from graspframe.robot_models.mounting import check_mounts

    path = _sunk_leap_spec(leap_hand_dir, tmp_path, dorsal=True)
    hand = load_spec(path)
    assert set(check_mounts(default_registry().get_arm("kuka"), hand)) == {"dorsal"}
    from graspframe.checks.hand import _mount_check

    result = _mount_check(hand, default_registry().get_arm("kuka"))
    assert not result.problems
    assert any(
        line.startswith("bolted straight on: deepest: hand link 'palm_lower'")
        and line.endswith("; not used")
        for line in result.measured
    ), result.measured


@JACO2
def test_the_shipped_mounts_touch_the_flange_at_most_by_the_tolerance(
    leap_hand_dir, panda_description_dir, kinova_description_dir
):
    registry = default_registry()
    arms = ["kuka", "kuka_iiwa14", str(PANDA_SPEC), str(JACO2_SPEC)]
    hands = ["barrett", "karlsruhe", str(LEAP_HAND_SPEC)]
    for arm in arms:
        for hand in hands:
            robot = mount(registry.get_arm(arm), registry.get_hand(hand))
            deepest = mount_overlaps(robot, tolerance=-1.0)
            assert not deepest or deepest[0].depth <= MOUNT_OVERLAP_TOLERANCE, (arm, hand)


def test_a_mount_link_across_a_movable_joint_is_refused(leap_hand_dir, tmp_path):
    spec = LEAP_HAND_SPEC.read_text().replace('mount_link = "leap_mount"', 'mount_link = "pip"')
    path = tmp_path / "leap_pip.toml"
    path.write_text(spec.replace("${LEAP_HAND_DIR}", str(leap_hand_dir)))
    with pytest.raises(DescriptionError, match=r"'pip' is separated from the file's root"):
        load_spec(path)
    path.write_text(path.read_text().replace('mount_link = "pip"', 'mount_link = "wrist"'))
    with pytest.raises(DescriptionError, match=r"the mount link 'wrist' is not a link"):
        load_spec(path)
    both = path.read_text().replace(
        'mount_link = "wrist"', 'mount_link = "base"\nroot_link = "base"'
    )
    path.write_text(both)
    with pytest.raises(DescriptionError, match="give mount_link or its older name root_link"):
        load_spec(path)


@JACO2
def test_the_jaco2_stands_on_its_base_and_carries_the_hand_along_link_6s_minus_z(
    kinova_description_dir,
):
    arm = load_spec(JACO2_SPEC)
    model = CollisionModel(model_of(arm))
    # Rooted at Kinova's base frame, one fixed joint below the file's root.
    np.testing.assert_allclose(model.T_root_frame("j2s6s200_link_base"), np.eye(4), atol=1e-12)
    q = dict(zip(arm.joint_names, arm.home_q, strict=True))
    model.place(q)
    T_link6, T_flange = model.T_root_frame("j2s6s200_link_6"), model.T_root_frame("jaco_flange")
    np.testing.assert_allclose(T_flange[:3, 2], -T_link6[:3, 2], atol=1e-6)
    # Kinova's tool frame approaches along its +x: the flange's +z.
    ee = model_of(load_spec(JACO2_SPEC)).link_names
    assert "j2s6s200_end_effector" not in ee and "j2s6s200_link_finger_1" not in ee
    assert T_flange[2, 2] < -0.99  # home: the flange points down
    # The vendor's hand housing on link_6 is left out; the continuous joints are revolute.
    assert not [link for link, _s, _T in model.shapes() if link == "j2s6s200_link_6"]
    assert all(math.isfinite(j.lower) and j.lower < 0 < j.upper for j in arm.joints[::3])


@JACO2
def test_an_arm_home_outside_its_limits_is_refused(kinova_description_dir, tmp_path):
    spec = JACO2_SPEC.read_text().replace(
        "home_q_deg = [0.0, 157.0, 287.0, 0.0, 130.0, 0.0]", "home_q_deg = [0, 0, 0, 0, 0, 0]"
    )
    path = tmp_path / "jaco_zero.toml"
    path.write_text(spec.replace("${KINOVA_DESCRIPTION_DIR}", str(kinova_description_dir)))
    with pytest.raises(DescriptionError, match=r"joint 'j2s6s200_joint_2' at 0 deg, outside"):
        load_spec(path)


def _held(result: dict) -> bool:
    outcome = result["outcome"]
    return bool(outcome["held_after_lift"] and outcome["held_under_disturbance"])


@pytest.mark.slow
@pytest.mark.parametrize("arm", ["kuka", "panda"])
def test_a_rerooted_hand_mounted_at_a_frame_holds_on_an_arm(
    leap_hand_dir, panda_description_dir, tmp_path, arm
):
    before = folder_state(leap_hand_dir)
    spec = _leap_spec(tmp_path, _leap_rooted_at_its_palm(leap_hand_dir, tmp_path), MOUNT_FRAME)
    request = RunRequest(
        hand=str(spec),
        arm="kuka" if arm == "kuka" else str(PANDA_SPEC),
        grasp=HumanGrasp.POWER_SPHERE,
        out_root=str(tmp_path / "runs"),
        record=False,
    )
    result = run_grasp(request, default_registry()).to_json()
    assert result["status"] == "ok" and _held(result), result["outcome"]["failure_reason"]
    assert folder_state(leap_hand_dir) == before


@pytest.mark.slow
@JACO2
def test_the_jaco2_carries_a_built_in_hand_through_the_demo(kinova_description_dir, tmp_path):
    before = folder_state(kinova_description_dir)
    request = RunRequest(
        hand="karlsruhe", arm=str(JACO2_SPEC), out_root=str(tmp_path), record=False
    )
    result = run_grasp(request, default_registry()).to_json()
    assert result["status"] == "ok" and _held(result), result["outcome"]["failure_reason"]
    assert folder_state(kinova_description_dir) == before
