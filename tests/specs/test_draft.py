"""`spec draft`: a hand spec drafted from a URDF, on the built-in hands' URDFs (where the
hand-written descriptions give the answer), the vendor hands as shipped, a vendor model
renamed and re-rooted at test time, and bad input."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from conftest import THIRD_PARTY, _vendor_dir

from graspframe.checks.hand import check_hand_report
from graspframe.checks.self_collision import posture_collisions
from graspframe.cli.commands import main
from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import rpy_from_R
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.specs import load_spec
from graspframe.specs.draft import draft_hand
from graspframe.specs.draft_text import generic_wrap, spec_text

ROBOTS = Path(__file__).resolve().parents[2] / "robots"


def _written(draft, folder: Path) -> Path:
    tables, grasp_map = generic_wrap(draft)
    path = folder / f"{draft.name}.toml"
    path.write_text(spec_text(draft, tables, grasp_map))
    return path


def _palm_z_in_root(spec: Path) -> np.ndarray:
    hand = load_spec(spec)
    model = CollisionModel(model_of(hand))
    return model.T_root_frame(hand.palm_frame)[:3, 2]


@pytest.mark.parametrize(
    ("hand_name", "thumb_link"), [("barrett", "bh_f3_tip"), ("karlsruhe", "kh_thumb_tip")]
)
def test_the_draft_of_a_builtin_hand_finds_what_its_description_says(
    hand_name, thumb_link, tmp_path
):
    draft = draft_hand(ROBOTS / hand_name / f"{hand_name}.urdf")
    assert draft.thumb == "thumb" and thumb_link in draft.fingers["thumb"].links
    builtin = default_registry().get_hand(hand_name)
    assert len(draft.fingers) == len(builtin.real_fingers) - 1  # the palm is not a finger
    # Every curling joint closes towards the larger side of its range: positive here.
    assert all(sign > 0 for f in draft.fingers.values() for sign in f.closing_sign.values())
    # The palm frame's +z is the built-in one's (the hand-written palm frame).
    model = CollisionModel(model_of(builtin))
    z_builtin = model.T_root_frame(builtin.palm_frame)[:3, 2]
    z_draft = _palm_z_in_root(_written(draft, tmp_path))
    assert math.degrees(math.acos(np.clip(z_builtin @ z_draft, -1, 1))) < 5.0
    # The drafted spec loads and passes the description check (the palm frame's +z out
    # of the palm, on its surface, the pad clear of the fingers).
    _passed, lines = check_hand_report(load_spec(_written(draft, tmp_path)))
    assert "1. the description against its model" in lines[1] and ": passed" in lines[1], lines


# The palm's direction in the root frame at q = 0 where the models' README gives it
# (dex-urdf turns LEAP, Ability and Shadow into one convention: the palm faces +x).
VENDOR_HANDS = [
    ("leap_hand/leap_hand_right.urdf", 4, "thumb_tip_head", [], (1, 0, 0)),
    ("ability_hand/ability_hand_right.urdf", 5, "thumb_tip", [], (1, 0, 0)),
    ("shadow_hand/shadow_hand_right.urdf", 5, "thtip", ["joints above the palm (WRJ2"], (1, 0, 0)),
    (
        "barrett_hand/bhand_model.urdf",
        3,
        "finger_3_dist_link",
        ["gives no joint effort"],
        (0, 0, 1),
    ),
]


@pytest.mark.parametrize(("urdf", "fingers", "thumb_link", "notes", "palm"), VENDOR_HANDS)
def test_the_vendor_hands_are_drafted_as_shipped(urdf, fingers, thumb_link, notes, palm, tmp_path):
    _vendor_dir("hands")
    draft = draft_hand(THIRD_PARTY / "hands" / urdf)
    assert len(draft.fingers) == fingers
    assert thumb_link in draft.fingers["thumb"].links
    for note in notes:
        assert any(note in line for line in draft.notes), draft.notes
    spec = _written(draft, tmp_path)
    hand = load_spec(spec)
    # What could not be decided is named in the file.
    for note in draft.notes:
        assert f"# NOT DECIDED: {note}" in spec.read_text()
    assert _palm_z_in_root(spec) @ np.array(palm, dtype=float) > 0.9
    assert hand.fingertip_frames["thumb"]
    assert hand.synchronised_closing  # the closing the synthesis plans
    _passed, lines = check_hand_report(hand)
    if "bhand" not in urdf:  # the vendor Barrett's finger 3 lies over its palm: see notes
        assert ": passed" in lines[1], lines


def _renamed_and_rerooted(urdf: Path, folder: Path) -> Path:
    """The vendor URDF with every link and joint renamed and a new root turned 90 deg
    about x (meshes by absolute path)."""
    tree = ET.parse(urdf)
    robot = tree.getroot()
    for element in robot.iter():
        for key in ("name", "link", "joint"):
            if (
                element.tag in ("link", "joint", "parent", "child", "mimic")
                and key in element.attrib
            ):
                element.set(key, f"v2_{element.get(key)}")
        if element.tag == "mesh":
            element.set("filename", str((urdf.parent / element.get("filename", "")).resolve()))
    old_root = "v2_base"
    ET.SubElement(robot, "link", name="v2_mount")
    joint = ET.SubElement(robot, "joint", name="v2_mount_joint", type="fixed")
    ET.SubElement(joint, "parent", link="v2_mount")
    ET.SubElement(joint, "child", link=old_root)
    ET.SubElement(joint, "origin", xyz="0 0 0.02", rpy=f"{math.pi / 2} 0 0")
    path = folder / "renamed.urdf"
    tree.write(path)
    return path


def test_a_vendor_hand_renamed_and_rerooted_is_drafted_alike(tmp_path):
    leap = _vendor_dir("hands", "leap_hand") / "leap_hand_right.urdf"
    draft = draft_hand(_renamed_and_rerooted(leap, tmp_path))
    assert draft.root_link == "v2_mount" and draft.palm_link == "v2_palm_lower"
    assert "v2_thumb_tip_head" in draft.fingers["thumb"].links and len(draft.fingers) == 4
    # The palm faced +x in the old root; the new root is turned 90 deg about x: still +x.
    z = _palm_z_in_root(_written(draft, tmp_path))
    assert z @ np.array([1.0, 0.0, 0.0]) > 0.9


def test_a_urdf_without_moving_joints_is_refused(tmp_path):
    urdf = tmp_path / "block.urdf"
    urdf.write_text(
        '<robot name="block"><link name="a"><collision><geometry><box size="0.1 0.1 0.1"/>'
        "</geometry></collision></link></robot>"
    )
    with pytest.raises(DescriptionError, match="no moving joint, so no finger to draft"):
        draft_hand(urdf)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["spec", "draft", "missing.urdf", "--out", "x.toml"], "URDF not found: missing.urdf"),
        (
            ["spec", "draft", "{urdf}", "--out", "x.txt", "--no-synthesize"],
            "--out must name a .toml",
        ),
        (
            ["spec", "draft", "{urdf}", "--out", "x.toml", "--workers", "0"],
            "--workers must be 1 or more (grasps synthesised at once), got 0",
        ),
        (
            ["check-hand", "x.toml", "--synthesize", "--workers", "0"],
            "--workers must be 1 or more",
        ),
    ],
)
def test_bad_draft_arguments_get_one_line(args, message, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    urdf = str(ROBOTS / "barrett" / "barrett.urdf")
    assert main([a.replace("{urdf}", urdf) for a in args]) == 1
    err = capsys.readouterr().err
    assert re.search(re.escape(message), err) and len(err.strip().splitlines()) == 1


def test_a_posture_never_rounds_past_a_joint_limit():
    from graspframe.specs.draft_kinematics import Joint
    from graspframe.specs.draft_text import posture_table

    joint = Joint("12", "revolute", "a", "b", -0.349, 2.094, 1.0, 1.0, None)
    lines = posture_table("p", "open", {"12": -0.349}, {"12": joint})
    value = float(lines[1].split("=")[1])
    assert math.radians(value) >= -0.349 and value == pytest.approx(-19.99, abs=0.01)


@pytest.mark.parametrize("urdf", ["karlsruhe", "leap_hand/leap_hand_right.urdf"])
def test_the_drafted_pad_clears_the_thumb_at_every_placing(urdf, tmp_path):
    """A thumb turned into opposition lies over the palm (the Karlsruhe's at 90 deg):
    the drafted pad is cut back from it at any placing, not only at rest, so such a
    posture is not a self-collision of the thumb with the pad."""
    if urdf == "karlsruhe":
        path = ROBOTS / "karlsruhe" / "karlsruhe.urdf"
    else:
        path = _vendor_dir("hands") / urdf
    draft = draft_hand(path)
    hand = load_spec(_written(draft, tmp_path))
    model = CollisionModel(model_of(hand))
    rest = draft.rest_q()
    placing = draft.fingers["thumb"].placing
    assert placing
    for fraction in (0.0, 0.3, 0.7, 1.0):  # 0.3 and 0.7 are not sampled by the draft
        q = dict(rest)
        for name in placing:
            joint = draft.joints[name]
            q[name] = joint.lower + fraction * (joint.upper - joint.lower)
        pairs = posture_collisions(model, hand.with_model_followers(q))
        assert not [pair for pair in pairs if draft.pad_frame in pair], (fraction, pairs)


@pytest.mark.parametrize("urdf", ["karlsruhe", "leap", "leap renamed and rerooted"])
def test_a_drafted_hand_mounts_on_an_arm_straight_and_through_a_dorsal_plate(urdf, tmp_path):
    """Bolted at its root link, the LEAP hand's palm reaches 2 mm behind the root's frame,
    into the arm's last link: the draft moves the flange's face back by that much. It
    proposes a plate on the back of the palm as a second mounting. Both clear the KUKA
    and the drafted palm frame is where the plate's flange axis points."""
    from graspframe.robot_models.mounting import check_mounts, mount_overlaps

    if urdf == "karlsruhe":
        path = ROBOTS / "karlsruhe" / "karlsruhe.urdf"
    else:
        path = _vendor_dir("hands") / "leap_hand" / "leap_hand_right.urdf"
        if "rerooted" in urdf:
            path = _renamed_and_rerooted(path, tmp_path)
    draft = draft_hand(path)
    hand = load_spec(_written(draft, tmp_path))
    robots = check_mounts(default_registry().get_arm("kuka"), hand)
    assert set(robots) == {None, "dorsal"}
    for robot in robots.values():
        touching = mount_overlaps(robot, tolerance=-1.0)
        assert not touching or touching[0].depth <= 0.0005, touching[0].describe()
    if urdf != "karlsruhe":
        assert draft.behind_root > 0.001 and hand.root_link == draft.mount_frame
    # Through the plate, the flange's axis is the palm normal.
    model = CollisionModel(model_of(hand))
    T_root_palm = model.T_root_frame(hand.palm_frame)
    T_root_plate = model.T_root_frame(draft.dorsal_frame)
    assert T_root_palm[:3, 2] @ T_root_plate[:3, 2] > 0.999
    assert draft.back_of_palm is not None and draft.back_of_palm > 0.01


@pytest.mark.parametrize("hand_name", ["barrett", "karlsruhe"])
def test_a_small_box_proud_of_the_palm_does_not_move_the_palm_frame_onto_it(hand_name, tmp_path):
    """A pad standing proud of the palm by its edge (the Shadow hand's thenar boxes, 10 mm
    over its palm by the wrist) is a bump, not the palm surface: the palm frame stays
    where it is on the plain palm, not on the bump's top at the palm's corner."""
    urdf = ROBOTS / hand_name / f"{hand_name}.urdf"
    plain = draft_hand(urdf)
    T = plain.T_palmlink_palm
    # an 8 x 8 mm box (the palm frame's axes), 8 mm proud of the palm, 20 mm off its middle:
    # about 1 % of the palm's outline, under the 3 % that makes a layer the palm surface
    centre = T[:3, :3] @ np.array([-0.02, 0.02, -0.002]) + T[:3, 3]
    tree = ET.parse(urdf)
    link = tree.getroot().find(f"link[@name='{plain.palm_link}']")
    collision = ET.SubElement(link, "collision")
    roll, pitch, yaw = rpy_from_R(T[:3, :3])
    ET.SubElement(collision, "origin", xyz=" ".join(map(str, centre)), rpy=f"{roll} {pitch} {yaw}")
    ET.SubElement(ET.SubElement(collision, "geometry"), "box", size="0.008 0.008 0.02")
    bumped_urdf = tmp_path / "bumped.urdf"
    tree.write(bumped_urdf)
    bumped = draft_hand(bumped_urdf)
    moved_mm = 1000 * np.linalg.norm(bumped.T_palmlink_palm[:3, 3] - T[:3, 3])
    assert moved_mm < 2.0, f"the palm frame moved {moved_mm:.1f} mm onto the bump"


def test_the_shadow_hands_palm_frame_lies_in_the_middle_of_its_palm():
    _vendor_dir("hands")
    draft = draft_hand(THIRD_PARTY / "hands" / "shadow_hand" / "shadow_hand_right.urdf")
    # the palm link's frame: fingers along +z, the palm 95 mm long from the wrist and 70
    # mm across (x), its face towards -y (the URDF's collision boxes)
    x, y, z = draft.T_palmlink_palm[:3, 3]
    assert 0.025 < z < 0.07 and -0.02 < x < 0.03 and y < -0.01, (x, y, z)
