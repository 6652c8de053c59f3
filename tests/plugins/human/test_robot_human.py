"""The human right hand model: segment lengths against Buchholz et al. 1992, frames,
coupling, postures.

Positions come from Pinocchio forward kinematics of the shipped URDF (and of a 170 mm hand
generated for the test). Tolerances, with their reasons:
- 0.5 mm on segment lengths (the brief's tolerance); the URDF stores 6 significant digits
  (~1e-7 m), so the real error is far smaller and anything near 0.5 mm is a modelling bug.
- 1 mm on delta: the description keeps it to 0.1 mm.
- 1e-6 m on the uniform scaling of a generated hand: only the 6-digit rounding differs.
- 1e-5 rad on SAPIEN limits: SAPIEN stores them as float32.
- 0.03 rad on the DIP following 2/3 of the PIP in SAPIEN: its tendon is a stiff spring
  (stiffness 1e5), not a rigid constraint; a broken coupling is off by ~0.3 rad.
"""

from __future__ import annotations

import hashlib
import json
import math
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from graspframe_human.description import (
    DIGITS,
    FINGERS,
    HAND_LENGTH,
    HUMAN,
    PALM_FRAME,
    PALM_SENSOR_LINK,
    ROOT_LINK,
)

from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.model_files.urdf_model import read_model
from graspframe.robot_models.model import CollisionModel, model_of, summarize_urdf

ROOT = Path(__file__).parents[3]
MM = 1e-3
DEG = math.pi / 180.0
LENGTH_TOL = 0.5 * MM
DELTA_TOL = 1.0 * MM
HAND = HUMAN

# Buchholz et al. 1992 (docs/robots/human.md), segment length / hand length.
BUCHHOLZ = {
    "thumb": (0.251, 0.196, 0.158),
    "index": (0.374, 0.265, 0.143, 0.097),
    "middle": (0.373, 0.277, 0.170, 0.108),
    "ring": (0.336, 0.259, 0.165, 0.107),
    "little": (0.295, 0.206, 0.117, 0.093),
}
# The frames that bound each segment: (from, to), in the order of the ratios above.
SEGMENT_FRAMES = {
    "thumb": (
        ("hh_thumb_cmc_flex", "hh_thumb_mcp"),
        ("hh_thumb_mcp", "hh_thumb_ip"),
        ("hh_thumb_ip", "hh_thumb_tip"),
    ),
    **{
        f: (
            (f"hh_{f}_metacarpal", f"hh_{f}_abd"),  # metacarpal base to knuckle
            (f"hh_{f}_mcp", f"hh_{f}_pip"),
            (f"hh_{f}_pip", f"hh_{f}_dip"),
            (f"hh_{f}_dip", f"hh_{f}_tip"),
        )
        for f in FINGERS
    },
}
# Some bent configuration [deg] (segment lengths must not depend on the pose).
BENT = {
    "hh_thumb_cmc_abd": 50,
    "hh_thumb_cmc_flex": 20,
    "hh_thumb_mcp": 30,
    "hh_thumb_ip": 40,
    **{f"hh_{f}_abd": 8 for f in FINGERS},
    **{f"hh_{f}_mcp": 40 for f in FINGERS},
    **{f"hh_{f}_pip": 60 for f in FINGERS},
}


def _generate(tmp: Path, hand_length: float | None = None) -> Path:
    """Run the generator as a user does; return the written URDF."""
    out = tmp / "human.urdf"
    cmd = [sys.executable, "-m", "tools.robot_models.human", "--out", str(out)]
    if hand_length is not None:
        cmd += ["--hand-length", str(hand_length)]
    subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True)
    return out


@pytest.fixture(scope="module")
def small_hand_urdf(tmp_path_factory) -> Path:
    return _generate(tmp_path_factory.mktemp("human170"), 0.17)


class Kinematics:
    """Forward kinematics of a hand URDF (mimic joints as ordinary joints: q gives DIPs
    at 2/3 of their PIP unless told otherwise)."""

    def __init__(self, path):
        self.model = pin.buildModelFromUrdf(str(path), False)
        self.data = self.model.createData()

    def place(self, q_rad: dict[str, float], couple: bool = True) -> None:
        q_rad = HAND.with_model_followers(q_rad) if couple else dict(q_rad)
        q = pin.neutral(self.model)
        for name, value in q_rad.items():
            q[self.model.joints[self.model.getJointId(name)].idx_q] = value
        pin.forwardKinematics(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)

    def T(self, frame: str) -> pin.SE3:
        return self.data.oMf[self.model.getFrameId(frame)]

    def in_palm(self, frame: str) -> np.ndarray:
        """Origin of a frame in the palm frame [m]."""
        return self.T(PALM_FRAME).actInv(self.T(frame).translation)


@pytest.fixture(scope="module")
def kin():
    return Kinematics(HAND.model_path)


def _shape_mass(path) -> float:
    """[kg] summed over links with collision shapes (marker links carry a token mass)."""
    links = ET.parse(path).getroot().iter("link")
    return sum(
        float(link.find("inertial/mass").get("value"))
        for link in links
        if link.find("collision") is not None
    )


def _deg(q_deg):
    return {k: v * DEG for k, v in q_deg.items()}


# ---- the description ----------------------------------------------------------------


def test_joints_are_the_twenty_less_the_mimic_followers():
    urdf = summarize_urdf(model_of(HAND))
    assert len(urdf.joints) == 20
    dips = {f"hh_{f}_dip" for f in FINGERS}
    assert set(HAND.joint_names) == set(urdf.joints) - dips
    assert {(c.follower, c.leader) for c in HAND.couplings} == {
        (f"hh_{f}_dip", f"hh_{f}_pip") for f in FINGERS
    }
    assert all(c.in_model and c.multiplier == pytest.approx(2 / 3) for c in HAND.couplings)


def test_every_link_is_in_exactly_one_real_finger():
    links = summarize_urdf(model_of(HAND)).links
    listed = [link for finger_links in HAND.real_fingers.values() for link in finger_links]
    assert sorted(listed) == sorted(links)
    assert set(HAND.real_fingers) == {*DIGITS, PALM}
    assert PALM_SENSOR_LINK in HAND.real_fingers[PALM]
    assert HAND.root_link == ROOT_LINK


def test_mass_is_adult_like():
    model = pin.buildModelFromUrdf(str(HAND.model_path), False)
    total = sum(inertia.mass for inertia in model.inertias)
    assert 0.40 <= total <= 0.50
    assert HAND.mass == pytest.approx(total, abs=1e-3)


# ---- segment lengths and scaling -------------------------------------------------------


@pytest.mark.parametrize("hand_length", [HAND_LENGTH, 0.17])
@pytest.mark.parametrize("pose", ["zero", "bent"])
def test_segment_lengths_are_buchholz_ratios_times_hand_length(hand_length, pose, small_hand_urdf):
    path = HAND.model_path if hand_length == HAND_LENGTH else small_hand_urdf
    kin = Kinematics(path)
    kin.place(_deg(BENT) if pose == "bent" else {})
    for digit, ratios in BUCHHOLZ.items():
        for (a, b), ratio in zip(SEGMENT_FRAMES[digit], ratios, strict=True):
            length = np.linalg.norm(kin.T(b).translation - kin.T(a).translation)
            assert length == pytest.approx(ratio * hand_length, abs=LENGTH_TOL), (a, b)
    # The knuckle has two joints at one point: ab/adduction, then flexion.
    for f in FINGERS:
        gap = kin.T(f"hh_{f}_mcp").translation - kin.T(f"hh_{f}_abd").translation
        assert np.linalg.norm(gap) < 1e-6


@pytest.mark.parametrize("hand_length", [HAND_LENGTH, 0.17])
def test_hand_length_is_wrist_to_extended_middle_fingertip(hand_length, small_hand_urdf):
    kin = Kinematics(HAND.model_path if hand_length == HAND_LENGTH else small_hand_urdf)
    kin.place({})
    tip = kin.T("hh_middle_tip").translation  # in the root (wrist) frame
    assert tip[2] == pytest.approx(hand_length, abs=0.1 * MM)
    assert np.hypot(tip[0], tip[1]) < 0.02  # straight ahead, within the palm's width


def test_generator_scales_the_whole_hand_uniformly(kin, small_hand_urdf):
    small = Kinematics(small_hand_urdf)
    kin.place(_deg(BENT))
    small.place(_deg(BENT))
    scale = 0.17 / HAND_LENGTH
    for frame in kin.model.frames:
        if frame.name == "universe":
            continue
        np.testing.assert_allclose(
            small.T(frame.name).translation, scale * kin.T(frame.name).translation, atol=1e-6
        )
    # Same limits; mass (shapes of one density) scales with the volume.
    shipped = summarize_urdf(model_of(HAND)).joints
    assert summarize_urdf(read_model(small_hand_urdf)).joints == shipped

    assert _shape_mass(small_hand_urdf) == pytest.approx(
        _shape_mass(HAND.model_path) * scale**3, rel=1e-4
    )


# ---- the DIP coupling ------------------------------------------------------------------


def test_dip_is_a_mimic_of_pip_at_two_thirds_in_the_urdf():
    joints = {j.get("name"): j for j in ET.parse(HAND.model_path).getroot().iter("joint")}
    for f in FINGERS:
        mimic = joints[f"hh_{f}_dip"].find("mimic")
        assert mimic is not None, f
        assert mimic.get("joint") == f"hh_{f}_pip"
        assert float(mimic.get("multiplier")) == pytest.approx(2 / 3, abs=1e-5)
        assert float(mimic.get("offset")) == 0.0


def test_pinocchio_mimic_model_moves_the_dip_with_the_pip():
    model = pin.buildModelFromUrdf(str(HAND.model_path), True)
    data = model.createData()
    assert model.nq == 16  # the four DIPs are not free coordinates
    q = pin.neutral(model)
    for f in FINGERS:
        q[model.joints[model.getJointId(f"hh_{f}_pip")].idx_q] = 0.9
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)
    for f in FINGERS:
        R_mid_dist = (
            data.oMf[model.getFrameId(f"hh_{f}_intermediate")].rotation.T
            @ data.oMf[model.getFrameId(f"hh_{f}_distal")].rotation
        )
        angle = np.linalg.norm(pin.log3(R_mid_dist))
        assert angle == pytest.approx(0.6, abs=1e-6), f


# ---- frames ----------------------------------------------------------------------------


def test_palm_frame_is_right_handed_with_x_along_the_middle_finger(kin):
    kin.place({})
    R = kin.T(PALM_FRAME).rotation
    x, y, z = R[:, 0], R[:, 1], R[:, 2]
    np.testing.assert_allclose(np.cross(z, x), y, atol=1e-5)  # y = z x x
    middle = kin.T("hh_middle_tip").translation - kin.T("hh_middle_abd").translation
    assert middle / np.linalg.norm(middle) @ x > 0.999
    # Root frame: +z along the hand towards the fingers.
    root_z = kin.T(ROOT_LINK).rotation[:, 2]
    assert root_z @ x > 0.999


def test_thumb_is_on_the_minus_y_side_of_the_palm_frame(kin):
    # For a right hand with the palm (+z) facing up and the fingers (+x) pointing away,
    # y = z x x points left, and the thumb lies on the right: -y.
    kin.place({})
    knuckle_y = [kin.in_palm(f"hh_{f}_abd")[1] for f in FINGERS]
    assert knuckle_y == sorted(knuckle_y)  # index, middle, ring, little towards +y
    for frame in ("hh_thumb_cmc_abd", "hh_thumb_mcp", "hh_thumb_tip"):
        assert kin.in_palm(frame)[1] < knuckle_y[0], frame


@pytest.mark.parametrize("finger", FINGERS)
def test_flexing_moves_a_fingertip_to_the_palmar_side(kin, finger):
    kin.place({})
    straight = kin.in_palm(f"hh_{finger}_tip")
    kin.place(_deg({f"hh_{finger}_mcp": 60, f"hh_{finger}_pip": 60}))
    bent = kin.in_palm(f"hh_{finger}_tip")
    assert bent[2] - straight[2] > 30 * MM


def test_flexing_the_thumb_moves_its_tip_across_the_palm_in_front_of_it(kin):
    kin.place({})
    straight = kin.in_palm("hh_thumb_tip")
    kin.place(_deg({"hh_thumb_cmc_flex": 30, "hh_thumb_mcp": 40, "hh_thumb_ip": 60}))
    bent = kin.in_palm("hh_thumb_tip")
    assert straight[2] < 0.0 < 10 * MM < bent[2]  # from beside the palm to its palmar side
    assert bent[1] - straight[1] > 50 * MM  # towards the fingers (+y)


def test_thumb_abduction_lifts_it_out_of_the_palm_and_turns_its_pad_to_the_fingers(kin):
    kin.place({})
    flat = kin.in_palm("hh_thumb_tip")
    kin.place({"hh_thumb_cmc_abd": 90 * DEG})
    opposed = kin.in_palm("hh_thumb_tip")
    assert flat[2] < 0.0 < 0.08 < opposed[2]
    # The thumb pad (-x of the thumb links) faces the fingertips (+x) when opposed.
    R_palm_distal = kin.T(PALM_FRAME).rotation.T @ kin.T("hh_thumb_distal").rotation
    assert -R_palm_distal[0, 0] > 0.8


def test_palm_frame_origin_lies_on_the_palmar_surface():
    model = CollisionModel(model_of(HAND))
    T = model.T_root_frame(PALM_FRAME)
    origin, z = T[:3, 3], T[:3, 2]
    assert model.links_containing(origin + 20 * MM * z) == []  # 2 cm out: free space
    assert model.links_containing(origin - 10 * MM * z) == [ROOT_LINK]  # 1 cm in: palm
    # The origin is on the pad's outer face: 0.5 mm in is pad, 0.5 mm out is nothing.
    assert model.links_containing(origin - 0.5 * MM * z) == [PALM_SENSOR_LINK]
    assert model.links_containing(origin + 0.5 * MM * z) == []


def test_zero_pose_is_free_of_self_collision():
    model = CollisionModel(model_of(HAND))
    model.place({})
    assert model.colliding_links() == []


# ---- postures --------------------------------------------------------------------------


def test_each_human_grasp_has_its_own_posture():
    assert {g: HAND.grasp_map[g] for g in HumanGrasp} == {g: g.value for g in HumanGrasp}
    assert set(HAND.preshapes) == {g.value for g in HumanGrasp}


@pytest.mark.parametrize("name", [g.value for g in HumanGrasp])
def test_posture_sets_every_driven_joint(name):
    posture = HAND.preshapes[name]
    assert set(posture.open_q) == set(HAND.joint_names)
    assert set(posture.closed_q) == set(HAND.joint_names)


# SHA-256 of every posture's joint names and angles [rad] and delta [m], in order, each
# number as float.hex(): the postures fitted to the design objects (docs/robots/human.md),
# bit for bit. A deliberate refit changes it; anything else (how the table is written
# down) must not.
POSTURES_SHA256 = "39d3456f878a98ff31531d7bebe407024bf6c5cfee3118bdd6bd00b179a90e4b"


def test_postures_are_the_fitted_ones_bit_for_bit():
    rows = [
        [
            name,
            [[joint, q.hex()] for joint, q in posture.open_q.items()],
            [[joint, q.hex()] for joint, q in posture.closed_q.items()],
            posture.delta.hex(),
        ]
        for name, posture in HAND.preshapes.items()
    ]
    assert hashlib.sha256(json.dumps(rows).encode()).hexdigest() == POSTURES_SHA256


@pytest.mark.parametrize("name", [g.value for g in HumanGrasp])
def test_posture_delta_is_the_mean_fingertip_height_above_the_palm(kin, name):
    posture = HAND.preshapes[name]
    kin.place(posture.open_q)
    heights = [kin.in_palm(f"hh_{d}_tip")[2] for d in DIGITS]
    assert posture.delta == pytest.approx(np.mean(heights), abs=DELTA_TOL)


@pytest.mark.parametrize("name", [g.value for g in HumanGrasp])
def test_closing_a_posture_curls_every_digit_further(name):
    posture = HAND.preshapes[name]
    # In the pinch only thumb, index and middle close; ring and little stay curled aside.
    digits = ("thumb", "index", "middle") if name == HumanGrasp.PINCH.value else DIGITS
    for digit in digits:
        flexion = [j for j in HAND.joint_names if j.startswith(f"hh_{digit}_") and "abd" not in j]
        closing = sum(posture.closed_q[j] - posture.open_q[j] for j in flexion)
        assert closing > 5 * DEG, digit


@pytest.mark.parametrize("name", [g.value for g in HumanGrasp])
def test_postures_are_free_of_self_collision(name):
    # Open: the contract of every hand. Closed: reached in free space, so it must be too.
    posture = HAND.preshapes[name]
    model = CollisionModel(model_of(HAND))
    for q in (posture.open_q, posture.closed_q):
        model.place(HAND.with_model_followers(q))
        assert model.colliding_links() == []


def _tip_gap(kin, q, a="thumb", b="index"):
    kin.place(q)
    return np.linalg.norm(kin.in_palm(f"hh_{a}_tip") - kin.in_palm(f"hh_{b}_tip"))


def test_pinch_closes_thumb_and_index_tips_together(kin):
    pinch = HAND.preshape_for(HumanGrasp.PINCH)
    assert _tip_gap(kin, pinch.open_q) > 50 * MM  # room for a small object
    assert _tip_gap(kin, pinch.closed_q) < 15 * MM  # measured 3.8 mm
    # The other human grasps do not bring the tips that close in the open posture.
    for grasp in HumanGrasp:
        assert _tip_gap(kin, HAND.preshape_for(grasp).open_q) > 50 * MM, grasp


def _spread(q):
    return q["hh_little_abd"] - q["hh_index_abd"]


def test_power_sphere_spreads_the_fingers_more_than_large_diameter():
    sphere = HAND.preshape_for(HumanGrasp.POWER_SPHERE)
    cylinder = HAND.preshape_for(HumanGrasp.LARGE_DIAMETER)
    assert _spread(sphere.open_q) > _spread(cylinder.open_q) + 20 * DEG
    disc = HAND.preshape_for(HumanGrasp.PRECISION_DISC)
    assert _spread(disc.open_q) >= _spread(sphere.open_q)


def test_abducted_thumb_keeps_the_thumb_beside_the_palm_not_opposed():
    thumb_abd = {g: HAND.preshape_for(g).closed_q["hh_thumb_cmc_abd"] for g in HumanGrasp}
    others = [v for g, v in thumb_abd.items() if g != HumanGrasp.ABDUCTED_THUMB]
    assert thumb_abd[HumanGrasp.ABDUCTED_THUMB] < 40 * DEG < min(others)


def test_precision_disc_holds_the_fingertips_in_front_of_the_palm(kin):
    disc = HAND.preshape_for(HumanGrasp.PRECISION_DISC)
    for q in (disc.open_q, disc.closed_q):
        kin.place(q)
        for digit in DIGITS:
            assert kin.in_palm(f"hh_{digit}_tip")[2] > 40 * MM, digit


# ---- SAPIEN ----------------------------------------------------------------------------


def _sapien_hand():
    import sapien

    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(1 / 500)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    return scene, loader.load(str(HAND.model_path))


def test_sapien_enforces_the_dip_coupling():
    scene, articulation = _sapien_hand()
    joints = articulation.get_active_joints()
    names = [j.name for j in joints]
    target = 0.9  # [rad] on every PIP
    for joint in joints:
        if joint.name.endswith("_dip"):
            continue  # driven by the coupling only
        joint.set_drive_property(HAND.drive.stiffness, HAND.drive.damping, HAND.drive.force_limit)
        joint.set_drive_target(target if joint.name.endswith("_pip") else 0.0)
    for _ in range(1000):  # 2 s
        scene.step()
    q = dict(zip(names, articulation.get_qpos(), strict=True))
    for f in FINGERS:
        assert q[f"hh_{f}_pip"] == pytest.approx(target, abs=0.03), f
        assert q[f"hh_{f}_dip"] == pytest.approx(2 / 3 * q[f"hh_{f}_pip"], abs=0.03), f
