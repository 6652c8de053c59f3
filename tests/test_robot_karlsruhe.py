"""The Karlsruhe humanoid hand model: geometry against ROBOTS.md, frames, preshapes.

Positions come from Pinocchio forward kinematics of the shipped URDF. Tolerances:
- 0.1 mm on positions taken straight from ROBOTS.md, 1e-4 rad on published rotations:
  the URDF stores 6 significant digits (~1e-7 m, ~1e-5 rad), so anything larger is a
  modelling error, not rounding.
- 1 deg on the thumb axis tilt: ROBOTS.md says "roughly 60 deg"; we chose exactly 60.
- 1 mm on delta: the description keeps it to 0.1 mm.
"""

from __future__ import annotations

import importlib
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from graspframe_karlsruhe import plugin
from graspframe_karlsruhe.description import (
    FINGERTIP_FRAMES,
    JOINT_NAMES,
    KARLSRUHE_HAND,
    MODEL_FRAME,
    PALM_FRAME,
    PALM_SENSOR_LINK,
    ROOT_LINK,
)

from graspframe.grasps import PALM, THUMB, HumanGrasp, Preshape
from graspframe.robot_model import CollisionModel, summarize_urdf
from graspframe.testing import assert_hand_contract

ROOT = Path(__file__).parents[1]
MM = 1e-3
DEG = math.pi / 180.0
POSITION_TOL = 0.1 * MM
ROTATION_TOL = 1e-4  # [rad]
HAND = KARLSRUHE_HAND

# ROBOTS.md, "Karlsruhe humanoid hand": base joint position in the model frame [mm] and
# rotation of the finger about the model frame's y axis [deg].
PUBLISHED_FINGER_BASES = {
    "kh_index_prox": ((94.0, -1.25, 29.3), -10.0),
    "kh_middle_prox": ((94.3, -1.25, 3.5), 0.0),
    "kh_ring": ((82.0, -1.25, -19.6), 7.5),
    "kh_little": ((70.9, -1.25, -39.3), 10.0),
}
PUBLISHED_THUMB_BASE = (31.2, -0.24, 26.7)  # [mm]
THUMB_AXIS_TILT = 60.0  # [deg] ROBOTS.md "roughly 60"; the model uses exactly 60
# (proximal joint, next joint, length [mm]) of the published proximal segments
PUBLISHED_SEGMENTS = (
    ("kh_index_prox", "kh_index_dist", 38.3),
    ("kh_middle_prox", "kh_middle_dist", 38.3),
    ("kh_thumb_base", "kh_thumb_flex", 23.3),
)
# joint -> the fingertip it moves
TIP_OF_JOINT = {
    "kh_thumb_base": "kh_thumb_tip",
    "kh_thumb_flex": "kh_thumb_tip",
    "kh_index_prox": "kh_index_tip",
    "kh_index_dist": "kh_index_tip",
    "kh_middle_prox": "kh_middle_tip",
    "kh_middle_dist": "kh_middle_tip",
    "kh_ring": "kh_ring_tip",
    "kh_little": "kh_little_tip",
}


@pytest.fixture(scope="module")
def fk():
    """fk(q_by_joint) -> (model, data) after framesForwardKinematics; joints not given
    stay at 0."""
    model = pin.buildModelFromUrdf(str(HAND.model_path), False)

    def run(q_by_joint):
        data = model.createData()
        q = pin.neutral(model)
        for name, value in q_by_joint.items():
            q[model.joints[model.getJointId(name)].idx_q] = value
        pin.framesForwardKinematics(model, data, q)
        return model, data

    return run


def frame(model, data, name: str) -> pin.SE3:
    return data.oMf[model.getFrameId(name)]


def in_frame(model, data, reference: str, p_root) -> np.ndarray:
    """A root-frame point [m] expressed in frame `reference`."""
    return frame(model, data, reference).actInv(np.asarray(p_root, dtype=float))


def tip_in_palm(model, data, tip: str) -> np.ndarray:
    return in_frame(model, data, PALM_FRAME, frame(model, data, tip).translation)


def joint_in_palm(model, data, joint: str) -> np.ndarray:
    return in_frame(model, data, PALM_FRAME, data.oMi[model.getJointId(joint)].translation)


def Ry(angle_deg: float) -> np.ndarray:
    c, s = math.cos(angle_deg * DEG), math.sin(angle_deg * DEG)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def angle_between(a, b) -> float:
    """[rad] between two vectors."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return math.atan2(np.linalg.norm(np.cross(a, b)), float(a @ b))


# --- contract, plugin, model files ------------------------------------------------------


def test_contract():
    assert_hand_contract(HAND)


def test_plugin_registers_the_hand():
    registered = []
    plugin.graspframe_register_hands(registered.append)
    assert registered == [HAND]


def test_generator_reproduces_the_shipped_urdf(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT))  # tools/ is a source-tree folder, not installed
    generator = importlib.import_module("tools.robot_models.karlsruhe")
    written = generator.build().write(tmp_path / "karlsruhe.urdf")
    assert written.read_text() == HAND.model_path.read_text(), (
        "robots/karlsruhe/karlsruhe.urdf is stale: run python -m tools.robot_models.karlsruhe"
    )


def test_eight_joints_all_0_to_90_deg_and_no_couplings():
    urdf = summarize_urdf(str(HAND.model_path))
    assert sorted(urdf.joints) == sorted(JOINT_NAMES)
    assert HAND.couplings == ()  # no mimic joints; the palm flex is left out
    for joint in urdf.joints.values():
        # the URDF writes 1.5708 for pi/2
        assert (joint.lower, joint.upper) == pytest.approx((0.0, 90 * DEG), abs=1e-5)
    for spec in HAND.joints:
        assert (spec.lower, spec.upper) == pytest.approx((0.0, 90 * DEG), abs=1e-12)


def test_sapien_loads_the_same_joints_and_limits():
    sapien = pytest.importorskip("sapien")
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    art = loader.load(str(HAND.model_path))
    sapien_limits = {
        j.name: tuple(limits)
        for j, limits in zip(art.get_active_joints(), art.get_qlimits(), strict=True)
    }
    urdf = summarize_urdf(str(HAND.model_path))
    assert set(sapien_limits) == set(urdf.joints)
    for name, joint in urdf.joints.items():
        # SAPIEN keeps limits in float32: ~1e-7 relative.
        assert sapien_limits[name] == pytest.approx((joint.lower, joint.upper), abs=1e-5)
    links = {link.name for link in art.get_links()}
    assert set(HAND.finger_of_link()) <= links
    assert {PALM_FRAME, MODEL_FRAME, *FINGERTIP_FRAMES.values()} <= links


def test_sapien_holds_each_open_preshape_without_penetration():
    sapien = pytest.importorskip("sapien")
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(1 / 500)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    art = loader.load(str(HAND.model_path))
    joints = {j.name: j for j in art.get_active_joints()}
    gains = HAND.drive
    for joint in joints.values():
        joint.set_drive_property(gains.stiffness, gains.damping, gains.force_limit)
    for preshape in HAND.preshapes.values():
        art.set_qpos(np.zeros(len(joints)))  # from the flat hand, under gravity
        art.set_qvel(np.zeros(len(joints)))
        for name, value in preshape.open_q.items():
            joints[name].set_drive_target(value)
        for _ in range(1000):  # 2 s
            scene.step()
        q = dict(zip(joints, art.get_qpos(), strict=True))
        for name, value in preshape.open_q.items():
            # soft drives: gravity sags the fingers by a fraction of a degree
            assert q[name] == pytest.approx(value, abs=1 * DEG), (preshape.name, name)
        # PhysX reports shape pairs within its contact offset; none may overlap or push.
        for contact in scene.get_contacts():
            names = [body.entity.name for body in contact.bodies]
            for point in contact.points:
                assert point.separation > -0.5 * MM, f"{preshape.name}: {names} penetrate"
                assert np.linalg.norm(point.impulse) < 1e-6, f"{preshape.name}: {names} push"


def test_total_mass(fk):
    model, _ = fk({})
    total = sum(inertia.mass for inertia in model.inertias)
    assert total == pytest.approx(HAND.mass, abs=1e-3)
    assert 0.5 < total < 0.8  # OUR ASSUMPTION: a light fluidic hand


# --- geometry against ROBOTS.md --------------------------------------------------------


@pytest.mark.parametrize("joint", PUBLISHED_FINGER_BASES)
def test_finger_base_joints_sit_where_the_model_frame_says(fk, joint):
    model, data = fk({})
    p_mm, angle_deg = PUBLISHED_FINGER_BASES[joint]
    T_model_joint = frame(model, data, MODEL_FRAME).actInv(data.oMi[model.getJointId(joint)])
    np.testing.assert_allclose(T_model_joint.translation, np.array(p_mm) * MM, atol=POSITION_TOL)
    error = pin.log3(Ry(angle_deg).T @ T_model_joint.rotation)
    assert np.linalg.norm(error) < ROTATION_TOL
    # Meaning of that rotation: the straight finger points along Ry(angle) x, and it
    # flexes about Ry(angle) z, perpendicular to the model y (palm normal).
    R_root_model = frame(model, data, MODEL_FRAME).rotation
    tip = FINGERTIP_FRAMES[joint.removeprefix("kh_").split("_")[0]]
    p_model_tip = in_frame(model, data, MODEL_FRAME, frame(model, data, tip).translation)
    assert angle_between(p_model_tip - np.array(p_mm) * MM, Ry(angle_deg)[:, 0]) < ROTATION_TOL
    axis_model = R_root_model.T @ joint_axis(model, data, joint)
    assert angle_between(axis_model, Ry(angle_deg)[:, 2]) < ROTATION_TOL


def joint_axis(model, data, joint: str) -> np.ndarray:
    """Rotation axis of a revolute joint in the root frame (the Jacobian's angular part)."""
    joint_id = model.getJointId(joint)
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    J = pin.getJointJacobian(model, data, joint_id, pin.ReferenceFrame.WORLD)
    return J[3:, model.joints[joint_id].idx_v]


def test_thumb_base_position_and_axis_tilt(fk):
    model, data = fk({})
    T_model_joint = frame(model, data, MODEL_FRAME).actInv(
        data.oMi[model.getJointId("kh_thumb_base")]
    )
    np.testing.assert_allclose(
        T_model_joint.translation, np.array(PUBLISHED_THUMB_BASE) * MM, atol=POSITION_TOL
    )
    axis_model = frame(model, data, MODEL_FRAME).rotation.T @ joint_axis(
        model, data, "kh_thumb_base"
    )
    # angle between the axis and the palm plane (model x-z plane, normal model y)
    tilt = math.degrees(math.asin(abs(axis_model[1]) / np.linalg.norm(axis_model)))
    assert tilt == pytest.approx(THUMB_AXIS_TILT, abs=1.0)


@pytest.mark.parametrize(("joint", "next_joint", "length_mm"), PUBLISHED_SEGMENTS)
def test_proximal_segment_lengths(fk, joint, next_joint, length_mm):
    model, data = fk({})
    p = data.oMi[model.getJointId(joint)].translation
    p_next = data.oMi[model.getJointId(next_joint)].translation
    assert np.linalg.norm(p_next - p) == pytest.approx(length_mm * MM, abs=POSITION_TOL)


# --- frames -----------------------------------------------------------------------------


def test_palmar_side_is_model_plus_y_of_a_right_hand(fk):
    """Our reading of ROBOTS.md: the model frame is right-handed, so for a right hand with
    x to the fingers and z to the thumb side, +y points out of the palm."""
    model, data = fk({})
    R_root_model = frame(model, data, MODEL_FRAME).rotation
    R_model_palm = R_root_model.T @ frame(model, data, PALM_FRAME).rotation
    np.testing.assert_allclose(R_model_palm[:, 0], [1, 0, 0], atol=1e-5)  # palm x = model x
    np.testing.assert_allclose(R_model_palm[:, 2], [0, 1, 0], atol=1e-5)  # palm z = model y
    assert np.linalg.det(R_model_palm) == pytest.approx(1.0)
    # A right hand seen from its palm side, fingers up: the thumb is on the right, which
    # is palm -y (y = z x x points left); the little finger is on the left.
    thumb, index, little = (
        joint_in_palm(model, data, j) for j in ("kh_thumb_base", "kh_index_prox", "kh_little")
    )
    assert thumb[1] < 0 and index[1] < 0 < little[1]


@pytest.mark.parametrize("joint", JOINT_NAMES)
def test_flexing_moves_the_fingertip_to_the_palmar_side(fk, joint):
    tip = TIP_OF_JOINT[joint]
    model, data = fk({})
    before = tip_in_palm(model, data, tip)
    model, data = fk({joint: 30 * DEG})
    after = tip_in_palm(model, data, tip)
    assert after[2] - before[2] > 5 * MM  # a 30 deg turn lifts a tip by cm, not by rounding


def test_root_frame_is_the_wrist_interface_with_z_along_the_fingers(fk):
    model, data = fk({})
    assert model.frames[model.getFrameId(ROOT_LINK)].parentJoint == 0  # the root link
    R_root_model = frame(model, data, MODEL_FRAME).rotation
    np.testing.assert_allclose(R_root_model[:, 0], [0, 0, 1], atol=1e-5)  # fingers = +z
    # The hand extends along the flange axis: every tip is well out of the flange, the
    # longest finger (middle, 171 mm from the wrist) leans < 15 deg off +z (the mount is
    # centred on the palm's wrist face, the middle finger sits 28 mm to the thumb side).
    for tip in FINGERTIP_FRAMES.values():
        assert frame(model, data, tip).translation[2] > 0.05, tip
    p_root_middle = frame(model, data, "kh_middle_tip").translation
    assert p_root_middle[2] > 0.15
    assert angle_between(p_root_middle, [0, 0, 1]) < 15 * DEG
    # The palm body starts at the mounting face z = 0, centred on the root origin.
    shapes = CollisionModel(HAND.model_path)
    wrist_boxes = []
    for link, shape, T_root_shape in shapes.shapes():
        if link == ROOT_LINK and type(shape).__name__ == "Box":
            half = np.abs(T_root_shape[:3, :3]) @ shape.halfSide
            if abs(T_root_shape[2, 3] - half[2]) < 1e-9:  # its lowest face is at z = 0
                wrist_boxes.append(T_root_shape[:3, 3])
    assert len(wrist_boxes) == 1
    np.testing.assert_allclose(wrist_boxes[0][:2], [0.0, 0.0], atol=1e-6)
    assert shapes.links_containing([0, 0, 1 * MM]) == [ROOT_LINK]
    assert shapes.links_containing([0, 0, -1 * MM]) == []


@pytest.mark.parametrize("preshape", [None, Preshape.POWER, Preshape.WRAP])
def test_palm_frame_origin_is_on_the_palm_surface(preshape):
    """Open hand and the open volar preshapes: the palm must be reachable for the volar
    strategy, nothing in front of it, the palm body behind it."""
    shapes = CollisionModel(HAND.model_path)
    shapes.place({} if preshape is None else dict(HAND.preshape(preshape).open_q))
    T_root_palm = shapes.T_root_frame(PALM_FRAME)

    def along_z(distance):
        return (T_root_palm @ [0.0, 0.0, distance, 1.0])[:3]

    assert shapes.links_containing(along_z(0.02)) == []
    assert shapes.links_containing(along_z(0.5 * MM)) == []
    assert shapes.links_containing(along_z(-0.5 * MM)) == [PALM_SENSOR_LINK]  # the pad face
    assert ROOT_LINK in shapes.links_containing(along_z(-0.01))


def test_real_fingers():
    assert set(HAND.real_fingers) == {THUMB, "index", "middle", "ring", "little", PALM}
    assert set(HAND.real_fingers[PALM]) == {ROOT_LINK, PALM_SENSOR_LINK}
    assert HAND.palm_sensor_link == PALM_SENSOR_LINK


# --- collisions -------------------------------------------------------------------------


def test_thumb_swings_and_flexes_without_hitting_palm_or_fingers():
    """Every thumb pose on a 15 deg grid, fingers straight: moving between preshapes never
    drives the thumb through the palm, the pad or the index knuckle."""
    shapes = CollisionModel(HAND.model_path)
    for base in range(0, 91, 15):
        for flex in range(0, 91, 15):
            shapes.place({"kh_thumb_base": base * DEG, "kh_thumb_flex": flex * DEG})
            assert shapes.colliding_links() == [], (base, flex)


def test_fingers_close_without_hitting_each_other_or_the_pad():
    shapes = CollisionModel(HAND.model_path)
    fingers = [j for j in JOINT_NAMES if not j.startswith("kh_thumb")]
    for angle in range(0, 91, 15):
        shapes.place({j: angle * DEG for j in fingers})
        assert shapes.colliding_links() == [], angle


# --- preshapes and mapping --------------------------------------------------------------


def test_mapping_table_is_method_section_1():
    assert dict(HAND.grasp_map) == {
        HumanGrasp.LARGE_DIAMETER: Preshape.POWER,
        HumanGrasp.SMALL_DIAMETER: Preshape.WRAP,
        HumanGrasp.ABDUCTED_THUMB: Preshape.POWER,
        HumanGrasp.PINCH: Preshape.POWER,
        HumanGrasp.POWER_SPHERE: Preshape.SPHERE,
        HumanGrasp.PRECISION_DISC: Preshape.DISC,
    }


@pytest.mark.parametrize("name", list(HAND.preshapes))
def test_preshape_sets_every_joint_and_closes_the_fingers(name):
    preshape = HAND.preshapes[name]
    assert set(preshape.open_q) == set(JOINT_NAMES) == set(preshape.closed_q)
    for joint in JOINT_NAMES:
        if joint == "kh_thumb_base":  # places the thumb; it does not flex
            continue
        assert preshape.closed_q[joint] >= preshape.open_q[joint] + 30 * DEG, joint


@pytest.mark.parametrize("name", list(HAND.preshapes))
def test_delta_is_the_highest_closing_fingertip_above_the_palm(fk, name):
    preshape = HAND.preshapes[name]
    closing = {TIP_OF_JOINT[j] for j in JOINT_NAMES if preshape.closed_q[j] != preshape.open_q[j]}
    model, data = fk(preshape.open_q)
    height = max(tip_in_palm(model, data, tip)[2] for tip in closing)
    assert preshape.delta == pytest.approx(height, abs=1 * MM)


def test_wrap_keeps_the_thumb_alongside_and_the_others_oppose_it(fk):
    """Alongside: the thumb tip lies in the palm plane (below the palm surface) and
    farther out on the thumb side than the index fingertip. Opposed: the thumb tip stands
    above the palm surface and inside the palm's width (past the index base)."""

    def thumb_and_index(preshape):
        model, data = fk(HAND.preshape(preshape).open_q)
        return (
            tip_in_palm(model, data, "kh_thumb_tip"),
            tip_in_palm(model, data, "kh_index_tip"),
            joint_in_palm(model, data, "kh_index_prox"),
        )

    thumb, index_tip, _ = thumb_and_index(Preshape.WRAP)
    assert thumb[2] < 0.0
    assert thumb[1] < index_tip[1]
    wrap_height = thumb[2]
    for opposed in (Preshape.POWER, Preshape.SPHERE, Preshape.DISC):
        thumb, _, index_base = thumb_and_index(opposed)
        assert thumb[2] > wrap_height + 10 * MM, opposed
        assert thumb[2] > 0.0, opposed
        assert thumb[1] > index_base[1], opposed


def test_disc_opposes_the_thumb_more_and_sphere_curls_the_fingers_more():
    sphere, disc = HAND.preshape(Preshape.SPHERE), HAND.preshape(Preshape.DISC)
    fingers = [j for j in JOINT_NAMES if not j.startswith("kh_thumb")]
    for label in ("open_q", "closed_q"):
        s, d = getattr(sphere, label), getattr(disc, label)
        assert d["kh_thumb_base"] > s["kh_thumb_base"], label
        assert sum(s[j] for j in fingers) > sum(d[j] for j in fingers), label
