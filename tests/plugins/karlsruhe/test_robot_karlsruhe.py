"""The Karlsruhe humanoid hand model: published geometry, the thumb's opposition, frames,
preshapes, and the hand alone holding each grasp's default object.

Sources of the published numbers: the hand's GraspIt! model (Miller & Allen, IEEE RAM
2004) as used by Romero, Kjellstroem & Kragic (ICAR 2009) for the 8-DOF fluidic hand of
Gaiser et al. (IEEE-RAS Humanoids 2008).

Positions come from Pinocchio forward kinematics of the shipped URDF. Tolerances:
- 0.1 mm on published positions, 1e-4 rad on published rotations: the URDF stores 6
  significant digits (~1e-7 m, ~1e-5 rad), so anything larger is a modelling error.
- 1 mm on delta: the description keeps it to 0.1 mm.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from graspframe_karlsruhe.description import (
    FINGERTIP_FRAMES,
    JOINT_NAMES,
    KARLSRUHE_HAND,
    MODEL_FRAME,
    PALM_FRAME,
    PALM_SENSOR_LINK,
    ROOT_LINK,
)
from scipy.spatial.transform import Rotation

from graspframe.checks.grasps import closing_gaps, closing_problems
from graspframe.common.grasps import PALM, THUMB, HumanGrasp, Preshape
from graspframe.robot_models.model import CollisionModel, model_of, summarize_urdf

MM = 1e-3
DEG = math.pi / 180.0
POSITION_TOL = 0.1 * MM
ROTATION_TOL = 1e-4  # [rad]
HAND = KARLSRUHE_HAND

# Published, model frame: base joint position [mm] and rotation of the finger chain
# about the model frame's y axis [deg].
PUBLISHED_FINGER_BASES = {
    "kh_index_prox": ((94.0, -1.25, 29.3), -10.0),
    "kh_middle_prox": ((94.3, -1.25, 3.5), 0.0),
    "kh_ring": ((82.0, -1.25, -19.6), 7.5),
    "kh_little": ((70.9, -1.25, -39.3), 10.0),
}
INDEX_MIDDLE_PROXIMAL_MM = 38.3  # DH a of the index/middle proximal joint (alpha = 0)
# The thumb, exactly as in the GraspIt! model: translation, then rotations about the
# MOVING axes z, x, z [deg]; then two DH joints (d [mm], a [mm], alpha [deg]).
THUMB_BASE_MM = (31.1829, -0.2415, 26.6908)
THUMB_BASE_ZXZ_DEG = (-83.3914, 60.1651, 86.7012)
THUMB_DH = ((0.0, 23.3027, -90.0), (0.0, 0.0, 180.0))
# The lead engineer's check: 40 mm along x of the frame after joint 2 [mm], model frame.
THUMB_POINT_40MM = {
    (0, 0): (62.8, -0.2, 81.5),
    (90, 0): (25.7, 62.7, 29.9),
    (90, 90): (63.6, 26.9, 8.0),
}
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
FINGER_JOINTS = [j for j in JOINT_NAMES if not j.startswith("kh_thumb")]


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


def tip_in(model, data, reference: str, tip: str) -> np.ndarray:
    return in_frame(model, data, reference, frame(model, data, tip).translation)


def joint_in(model, data, reference: str, joint: str) -> np.ndarray:
    return in_frame(model, data, reference, data.oMi[model.getJointId(joint)].translation)


def T_model_joint(model, data, joint: str) -> pin.SE3:
    return frame(model, data, MODEL_FRAME).actInv(data.oMi[model.getJointId(joint)])


def Ry(angle_deg: float) -> np.ndarray:
    return Rotation.from_euler("y", angle_deg, degrees=True).as_matrix()


def dh(theta_deg: float, d_mm: float, a_mm: float, alpha_deg: float) -> pin.SE3:
    """One DH step [m]: rotation theta about z, d along z, a along x, alpha about x."""
    Rz = Rotation.from_euler("z", theta_deg, degrees=True).as_matrix()
    Rx = Rotation.from_euler("x", alpha_deg, degrees=True).as_matrix()
    return pin.SE3(Rz, np.array([0.0, 0.0, d_mm * MM])) * pin.SE3(Rx, np.array([a_mm * MM, 0, 0]))


def thumb_frame_after_joint_2(t1_deg, t2_deg, zxz="ZXZ") -> pin.SE3:
    """The published thumb chain in the model frame (zxz "ZXZ": moving axes)."""
    R = Rotation.from_euler(zxz, THUMB_BASE_ZXZ_DEG, degrees=True).as_matrix()
    T = pin.SE3(R, np.array(THUMB_BASE_MM) * MM)
    for theta, (d, a, alpha) in zip((t1_deg, t2_deg), THUMB_DH, strict=True):
        T = T * dh(theta, d, a, alpha)
    return T


def angle_between(a, b) -> float:
    """[rad] between two vectors."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return math.atan2(np.linalg.norm(np.cross(a, b)), float(a @ b))


def joint_axis(model, data, joint: str) -> np.ndarray:
    """Rotation axis of a revolute joint in the root frame (the Jacobian's angular part)."""
    joint_id = model.getJointId(joint)
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    J = pin.getJointJacobian(model, data, joint_id, pin.ReferenceFrame.WORLD)
    return J[3:, model.joints[joint_id].idx_v]


# --- joints and SAPIEN -----------------------------------------------------------------


def test_eight_joints_all_0_to_90_deg_and_no_couplings():
    urdf = summarize_urdf(model_of(HAND))
    assert sorted(urdf.joints) == sorted(JOINT_NAMES)
    assert HAND.couplings == ()
    for joint in urdf.joints.values():
        # the URDF writes 1.5708 for pi/2
        assert (joint.lower, joint.upper) == pytest.approx((0.0, 90 * DEG), abs=1e-5)
    for spec in HAND.joints:
        assert (spec.lower, spec.upper) == pytest.approx((0.0, 90 * DEG), abs=1e-12)


def test_model_and_fingertip_frames_are_links():
    links = summarize_urdf(model_of(HAND)).links
    assert {MODEL_FRAME, *FINGERTIP_FRAMES.values()} <= links


def test_sapien_holds_each_open_preshape():
    """The soft drives hold every open preshape against gravity (fingers up, root fixed)."""
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


def test_total_mass(fk):
    model, _ = fk({})
    total = sum(inertia.mass for inertia in model.inertias)
    assert total == pytest.approx(HAND.mass, abs=1e-3)
    assert 0.5 < total < 0.8  # OUR ASSUMPTION: a light fluidic hand


# --- published geometry ---------------------------------------------------------------


@pytest.mark.parametrize("joint", PUBLISHED_FINGER_BASES)
def test_finger_base_joints_sit_where_the_model_frame_says(fk, joint):
    model, data = fk({})
    p_mm, angle_deg = PUBLISHED_FINGER_BASES[joint]
    T = T_model_joint(model, data, joint)
    np.testing.assert_allclose(T.translation, np.array(p_mm) * MM, atol=POSITION_TOL)
    assert np.linalg.norm(pin.log3(Ry(angle_deg).T @ T.rotation)) < ROTATION_TOL
    # The straight finger points along the chain's x and flexes about the chain's z.
    R_root_model = frame(model, data, MODEL_FRAME).rotation
    tip = FINGERTIP_FRAMES[joint.removeprefix("kh_").split("_")[0]]
    p_model_tip = tip_in(model, data, MODEL_FRAME, tip)
    assert angle_between(p_model_tip - np.array(p_mm) * MM, Ry(angle_deg)[:, 0]) < ROTATION_TOL
    axis_model = R_root_model.T @ joint_axis(model, data, joint)
    assert angle_between(axis_model, Ry(angle_deg)[:, 2]) < ROTATION_TOL


@pytest.mark.parametrize("finger", ["index", "middle"])
def test_index_middle_distal_joint_ends_the_38_3_mm_proximal_segment(fk, finger):
    """DH a = 38.3 along the proximal's x, then the distal joint (a = 0, alpha = 0): the
    same axis direction, at every proximal angle."""
    for angle in (0.0, 40.0):
        model, data = fk({f"kh_{finger}_prox": angle * DEG})
        T_prox = data.oMi[model.getJointId(f"kh_{finger}_prox")]
        T_dist = data.oMi[model.getJointId(f"kh_{finger}_dist")]
        relative = T_prox.actInv(T_dist)
        np.testing.assert_allclose(
            relative.translation, [INDEX_MIDDLE_PROXIMAL_MM * MM, 0, 0], atol=POSITION_TOL
        )
        assert np.linalg.norm(pin.log3(relative.rotation)) < ROTATION_TOL


def test_thumb_base_is_the_published_transform_about_moving_axes(fk):
    model, data = fk({})
    T = T_model_joint(model, data, "kh_thumb_base")
    np.testing.assert_allclose(T.translation, np.array(THUMB_BASE_MM) * MM, atol=POSITION_TOL)
    R = Rotation.from_euler("ZXZ", THUMB_BASE_ZXZ_DEG, degrees=True).as_matrix()
    assert np.linalg.norm(pin.log3(R.T @ T.rotation)) < ROTATION_TOL
    axis_model = frame(model, data, MODEL_FRAME).rotation.T @ joint_axis(
        model, data, "kh_thumb_base"
    )
    assert angle_between(axis_model, R[:, 2]) < ROTATION_TOL  # joint 1 turns about its z


@pytest.mark.parametrize(("t1", "t2"), [(0, 0), (30, 60), (90, 0), (90, 90)])
def test_thumb_chain_is_the_published_dh_chain(fk, t1, t2):
    """The second joint's frame and the distal link follow the two DH steps exactly."""
    model, data = fk({"kh_thumb_base": t1 * DEG, "kh_thumb_flex": t2 * DEG})
    expected = thumb_frame_after_joint_2(t1, t2)
    T_model_distal = frame(model, data, MODEL_FRAME).actInv(frame(model, data, "kh_thumb_distal"))
    np.testing.assert_allclose(T_model_distal.translation, expected.translation, atol=POSITION_TOL)
    # x (along the distal segment) is the DH frame's; alpha_2 = 180 deg only flips y, z
    assert angle_between(T_model_distal.rotation[:, 0], expected.rotation[:, 0]) < ROTATION_TOL
    joint_2 = T_model_joint(model, data, "kh_thumb_flex")
    after_joint_1 = thumb_frame_after_joint_2(t1, 0.0) * dh(0, *THUMB_DH[1]).inverse()
    np.testing.assert_allclose(joint_2.translation, after_joint_1.translation, atol=POSITION_TOL)
    assert angle_between(joint_2.rotation[:, 2], after_joint_1.rotation[:, 2]) < ROTATION_TOL


@pytest.mark.parametrize(("t1", "t2"), list(THUMB_POINT_40MM))
def test_thumb_point_40_mm_out_is_where_the_published_chain_puts_it(fk, t1, t2):
    model, data = fk({"kh_thumb_base": t1 * DEG, "kh_thumb_flex": t2 * DEG})
    T_model_distal = frame(model, data, MODEL_FRAME).actInv(frame(model, data, "kh_thumb_distal"))
    point = T_model_distal.act(np.array([40 * MM, 0.0, 0.0]))
    np.testing.assert_allclose(point, np.array(THUMB_POINT_40MM[(t1, t2)]) * MM, atol=0.06 * MM)


def test_fixed_axes_reading_would_close_the_thumb_towards_the_wrist():
    """Why the rotations are about the moving axes: read about fixed axes, the closed
    thumb (90, 90) would end behind its own base, at the wrist, not on the fingers."""
    tip = {
        reading: thumb_frame_after_joint_2(90, 90, reading).act(np.array([0.05, 0, 0]))
        for reading in ("ZXZ", "zxz")
    }
    assert tip["zxz"][0] < THUMB_BASE_MM[0] * MM  # fixed axes: towards the wrist
    assert tip["ZXZ"][0] > THUMB_BASE_MM[0] * MM + 0.025  # moving axes: onto the fingers


# --- the thumb opposes the index and middle fingers ------------------------------------


def finger_gap(shapes: CollisionModel, finger_a: str, finger_b: str) -> float:
    """[m] smallest distance between the links of two real fingers (coal)."""
    import coal

    placed = list(shapes.shapes())
    links_a, links_b = set(HAND.real_fingers[finger_a]), set(HAND.real_fingers[finger_b])
    best = math.inf
    for link_a, shape_a, T_a in placed:
        for link_b, shape_b, T_b in placed:
            if link_a in links_a and link_b in links_b:
                distance = coal.distance(
                    shape_a,
                    coal.Transform3s(T_a[:3, :3], T_a[:3, 3]),
                    shape_b,
                    coal.Transform3s(T_b[:3, :3], T_b[:3, 3]),
                    coal.DistanceRequest(),
                    coal.DistanceResult(),
                )
                best = min(best, float(distance))
    return best


def test_closing_the_thumb_moves_it_onto_the_index_and_middle_fingers(fk):
    """Thumb raised (t1 = 90), fingers closed: flexing the thumb (t2 0 -> 90) moves its tip
    towards the fingers (+x in the model frame, never towards the wrist) and closes the
    gap to the index and the middle finger until they touch."""
    fingers_closed = {j: 90 * DEG for j in FINGER_JOINTS}
    shapes = CollisionModel(model_of(HAND))
    xs, gaps = [], {"index": [], "middle": []}
    for t2 in range(0, 91, 10):
        q = {**fingers_closed, "kh_thumb_base": 90 * DEG, "kh_thumb_flex": t2 * DEG}
        model, data = fk(q)
        xs.append(tip_in(model, data, MODEL_FRAME, "kh_thumb_tip")[0])
        shapes.place(q)
        for finger in gaps:
            gaps[finger].append(finger_gap(shapes, THUMB, finger))
    assert np.all(np.diff(xs) > 0)
    for finger, values in gaps.items():
        assert values[0] > 10 * MM, finger
        touching = next(i for i, gap in enumerate(values) if gap <= 1 * MM)
        assert np.all(np.diff(values[: touching + 1]) < 0), finger


@pytest.mark.parametrize("name", [n for n in HAND.preshapes if HAND.preshapes[n].opposed])
def test_opposed_preshapes_close_the_thumb_onto_index_and_middle(name):
    preshape = HAND.preshapes[name]
    assert set(preshape.opposed) == {(THUMB, "index"), (THUMB, "middle")}
    for gap in closing_gaps(HAND, preshape):
        assert gap.closed_gap < 15 * MM, gap
        assert gap.closed_gap < gap.open_gap, gap


def test_closing_problems_none():
    assert closing_problems(HAND) == []


# --- frames -----------------------------------------------------------------------------


def test_palmar_side_is_model_plus_y_of_a_right_hand(fk):
    """Fingers flex towards model +y (published); for a right hand with x to the fingers
    and z to the thumb side, a right-handed frame puts +y out of the palm."""
    model, data = fk({})
    R_root_model = frame(model, data, MODEL_FRAME).rotation
    R_model_palm = R_root_model.T @ frame(model, data, PALM_FRAME).rotation
    np.testing.assert_allclose(R_model_palm[:, 0], [1, 0, 0], atol=1e-5)  # palm x = model x
    np.testing.assert_allclose(R_model_palm[:, 2], [0, 1, 0], atol=1e-5)  # palm z = model y
    assert np.linalg.det(R_model_palm) == pytest.approx(1.0)
    thumb, index, little = (
        joint_in(model, data, PALM_FRAME, j)
        for j in ("kh_thumb_base", "kh_index_prox", "kh_little")
    )
    assert thumb[1] < 0 and index[1] < 0 < little[1]  # palm y points to the little finger


@pytest.mark.parametrize("joint", FINGER_JOINTS)
def test_flexing_a_finger_moves_its_tip_to_the_palmar_side(fk, joint):
    tip = TIP_OF_JOINT[joint]
    model, data = fk({})
    before = tip_in(model, data, PALM_FRAME, tip)
    model, data = fk({joint: 30 * DEG})
    after = tip_in(model, data, PALM_FRAME, tip)
    assert after[2] - before[2] > 5 * MM


def test_thumb_base_raises_the_thumb_and_thumb_flex_swings_it_to_the_fingers(fk):
    model, data = fk({})
    flat = tip_in(model, data, PALM_FRAME, "kh_thumb_tip")
    model, data = fk({"kh_thumb_base": 90 * DEG})
    raised = tip_in(model, data, PALM_FRAME, "kh_thumb_tip")
    model, data = fk({"kh_thumb_base": 90 * DEG, "kh_thumb_flex": 60 * DEG})
    flexed = tip_in(model, data, PALM_FRAME, "kh_thumb_tip")
    assert flat[2] < 0.0 < 50 * MM < raised[2]  # in the palm plane, then standing up
    assert flexed[0] - raised[0] > 30 * MM  # towards the fingertips
    assert flexed[1] - raised[1] > 15 * MM  # from the thumb side towards the middle


def test_root_frame_is_the_wrist_interface_with_z_along_the_fingers(fk):
    model, data = fk({})
    assert model.frames[model.getFrameId(ROOT_LINK)].parentJoint == 0  # the root link
    R_root_model = frame(model, data, MODEL_FRAME).rotation
    np.testing.assert_allclose(R_root_model[:, 0], [0, 0, 1], atol=1e-5)  # fingers = +z
    for tip in FINGERTIP_FRAMES.values():
        assert frame(model, data, tip).translation[2] > 0.05, tip
    p_root_middle = frame(model, data, "kh_middle_tip").translation
    assert p_root_middle[2] > 0.15
    assert angle_between(p_root_middle, [0, 0, 1]) < 15 * DEG
    # The palm body starts at the mounting face z = 0, the wrist box centred on the origin.
    shapes = CollisionModel(model_of(HAND))
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
    """Open hand and the open volar preshapes: nothing in front of the palm centre, the
    pad face at it, the palm body behind it."""
    shapes = CollisionModel(model_of(HAND))
    shapes.place({} if preshape is None else dict(HAND.preshape(preshape).open_q))
    T_root_palm = shapes.T_root_frame(PALM_FRAME)

    def along_z(distance):
        return (T_root_palm @ [0.0, 0.0, distance, 1.0])[:3]

    assert shapes.links_containing(along_z(0.02)) == []
    assert shapes.links_containing(along_z(0.5 * MM)) == []
    assert shapes.links_containing(along_z(-0.5 * MM)) == [PALM_SENSOR_LINK]  # the pad face
    assert ROOT_LINK in shapes.links_containing(along_z(-0.01))


def test_palm_surface_is_level_with_the_palmar_side_of_the_finger_bases(fk):
    """The palm surface stands at most 3 mm in front of the finger bases' palmar side
    (base joint + finger radius): objects on the palm meet the flexing fingers, the palm
    does not hold them off (it stood 16 mm proud in an earlier model)."""
    model, data = fk({})
    shapes = CollisionModel(model_of(HAND))
    radius = {
        link: shape.radius for link, shape, _ in shapes.shapes() if type(shape).__name__ == "Sphere"
    }
    for joint, link in (("kh_index_prox", "kh_index_proximal"), ("kh_ring", "kh_ring_link")):
        base = joint_in(model, data, PALM_FRAME, joint)
        assert -3 * MM < base[2] + radius[link] <= 0.0, joint


def test_real_fingers():
    assert set(HAND.real_fingers) == {THUMB, "index", "middle", "ring", "little", PALM}
    assert set(HAND.real_fingers[PALM]) == {ROOT_LINK, PALM_SENSOR_LINK}
    assert HAND.palm_sensor_link == PALM_SENSOR_LINK


# --- collisions -------------------------------------------------------------------------


def test_fingers_close_without_hitting_each_other_or_the_palm():
    shapes = CollisionModel(model_of(HAND))
    for angle in range(0, 91, 15):
        shapes.place({j: angle * DEG for j in FINGER_JOINTS})
        assert shapes.colliding_links() == [], angle


@pytest.mark.parametrize("name", list(HAND.preshapes))
def test_the_thumb_stays_out_of_the_palm_while_a_preshape_closes(name):
    """Along each preshape's closing (open -> closed, linear), nothing collides with the
    palm body or pad (the fingertips may meet each other at the very end)."""
    preshape = HAND.preshapes[name]
    shapes = CollisionModel(model_of(HAND))
    palm_links = set(HAND.real_fingers[PALM])
    for s in np.linspace(0.0, 1.0, 11):
        q = {j: (1 - s) * preshape.open_q[j] + s * preshape.closed_q[j] for j in JOINT_NAMES}
        shapes.place(q)
        hits = [pair for pair in shapes.colliding_links() if palm_links & set(pair)]
        assert hits == [], (name, round(float(s), 1))
    shapes.place(dict(preshape.open_q))
    assert shapes.colliding_links() == [], name


# --- preshapes and mapping --------------------------------------------------------------


def test_mapping_table_is_the_methods():
    assert dict(HAND.grasp_map) == {
        HumanGrasp.LARGE_DIAMETER: Preshape.POWER,
        HumanGrasp.SMALL_DIAMETER: Preshape.WRAP,
        HumanGrasp.ABDUCTED_THUMB: Preshape.POWER,
        HumanGrasp.PINCH: Preshape.POWER,
        HumanGrasp.POWER_SPHERE: Preshape.SPHERE,
        HumanGrasp.PRECISION_DISC: Preshape.DISC,
    }


@pytest.mark.parametrize("name", list(HAND.preshapes))
def test_preshape_sets_every_joint_and_closes_thumb_index_and_middle(name):
    preshape = HAND.preshapes[name]
    assert set(preshape.open_q) == set(JOINT_NAMES) == set(preshape.closed_q)
    for finger in ("thumb", "index", "middle"):
        joints = [j for j in JOINT_NAMES if j.startswith(f"kh_{finger}")]
        closing = max(preshape.closed_q[j] - preshape.open_q[j] for j in joints)
        assert closing >= 30 * DEG, finger
    for joint in JOINT_NAMES:
        assert preshape.closed_q[joint] >= preshape.open_q[joint], joint


@pytest.mark.parametrize("name", list(HAND.preshapes))
def test_delta_is_the_highest_closing_fingertip_above_the_palm(fk, name):
    preshape = HAND.preshapes[name]
    closing = {TIP_OF_JOINT[j] for j in JOINT_NAMES if preshape.closed_q[j] != preshape.open_q[j]}
    model, data = fk(preshape.open_q)
    height = max(tip_in(model, data, PALM_FRAME, tip)[2] for tip in closing)
    assert preshape.delta == pytest.approx(height, abs=1 * MM)


@pytest.mark.parametrize("name", list(HAND.preshapes))
def test_design_object_sits_in_front_of_the_open_hand(name):
    """Each preshape declares the object it is shaped for; in the open preshape it
    overlaps no hand link (a volar design object rests on the palm)."""
    import coal

    preshape = HAND.preshapes[name]
    design = preshape.design_object
    assert design is not None
    shapes = CollisionModel(model_of(HAND))
    shapes.place(dict(preshape.open_q))
    T_root_palm = shapes.T_root_frame(PALM_FRAME)
    if design.shape == "sphere":
        geometry, R_palm_object = coal.Sphere(design.radius), np.eye(3)
    else:
        geometry = coal.Cylinder(design.radius, design.length)
        z = np.asarray(design.axis, float) / np.linalg.norm(design.axis)
        x = np.cross([0.0, 0.0, 1.0], z) if abs(z[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        x /= np.linalg.norm(x)
        R_palm_object = np.column_stack([x, np.cross(z, x), z])
    R = T_root_palm[:3, :3] @ R_palm_object
    p = (T_root_palm @ np.append(design.centre, 1.0))[:3]
    for link, shape, T in shapes.shapes():
        distance = coal.distance(
            shape,
            coal.Transform3s(T[:3, :3], T[:3, 3]),
            geometry,
            coal.Transform3s(R, p),
            coal.DistanceRequest(),
            coal.DistanceResult(),
        )
        assert distance > -0.5 * MM, (name, link)


def test_wrap_keeps_the_thumb_alongside_and_the_others_raise_it(fk):
    """Wrap: the thumb stays beside the index, out on the thumb side of it (palm -y) and
    within 15 mm of the palm plane: it never comes over the palm. The other preshapes
    raise it out of the palm (t1 >= 45 deg) and close it to t1 >= 80 deg."""
    wrap = HAND.preshape(Preshape.WRAP)
    for q in (wrap.open_q, wrap.closed_q):
        model, data = fk(q)
        thumb = tip_in(model, data, PALM_FRAME, "kh_thumb_tip")
        index_base = joint_in(model, data, PALM_FRAME, "kh_index_prox")
        assert abs(thumb[2]) < 15 * MM
        assert thumb[1] < index_base[1] - 15 * MM
    for name, preshape in HAND.preshapes.items():
        if name != Preshape.WRAP:
            assert preshape.open_q["kh_thumb_base"] >= 45 * DEG, name
            assert preshape.closed_q["kh_thumb_base"] >= 80 * DEG, name


def test_sphere_and_disc_differ_in_the_thumb_and_in_the_finger_curl(fk):
    """Sphere: the thumb stands up at the wrist end of the palm (t1 = 90) and the fingers
    round the ball (index to ring) start and end more curled. Disc: the thumb comes in
    from the side, beside the index, and sweeps across the palm towards the little
    finger, which stands as a post beside the disc (it does not curl: open = closed)."""
    sphere, disc = HAND.preshape(Preshape.SPHERE), HAND.preshape(Preshape.DISC)
    curling = [j for j in FINGER_JOINTS if j != "kh_little"]
    for label in ("open_q", "closed_q"):
        s, d = getattr(sphere, label), getattr(disc, label)
        assert sum(s[j] for j in curling) > sum(d[j] for j in curling), label
    assert disc.open_q["kh_little"] == disc.closed_q["kh_little"] == 90 * DEG
    tips = {}
    for name, preshape in (("sphere", sphere), ("disc", disc)):
        model, data = fk(preshape.open_q)
        tips[name] = tip_in(model, data, PALM_FRAME, "kh_thumb_tip")
        model, data = fk(preshape.closed_q)
        tips[name + " closed"] = tip_in(model, data, PALM_FRAME, "kh_thumb_tip")
    index_base = joint_in(*fk({}), PALM_FRAME, "kh_index_prox")
    assert tips["disc"][1] < index_base[1] - 15 * MM < tips["sphere"][1]  # beside the index
    assert tips["disc closed"][1] - tips["disc"][1] > 40 * MM  # sweeps across the palm


# --- the hand alone holds each grasp's default object ----------------------------------


def hand_alone_run(grasp: HumanGrasp, object_name: str | None = None):
    """The grasp as `graspframe run --hand karlsruhe --grasp G --mount floating` runs it:
    the human reference palm pose, the hand on the free base, the object on the table."""
    from graspframe_sapien.backend import SapienBackend

    from graspframe.checks.grasps import hand_alone_setup
    from graspframe.common.defaults import SCENE_OBJECT_XY
    from graspframe.motion.arm_motion import ArmMotion
    from graspframe.plugin_system.registry import default_registry
    from graspframe.strategy.execution import run_policy
    from graspframe.strategy.held_check import HeldTest
    from graspframe.strategy.method import MethodStrategy
    from graspframe.strategy.reference_poses import reference_placement

    registry = default_registry()
    obj = registry.get_object(object_name) if object_name else registry.default_object_for(grasp)
    placement = reference_placement(obj, registry.get_hand("human").preshape_for(grasp))
    setup = hand_alone_setup(HAND, grasp, obj, placement.T_object_palm, xy=SCENE_OBJECT_XY)
    checked = setup.checked
    with SapienBackend().create_world(setup.config) as world:
        motion = ArmMotion(world, checked.robot, checked.T_world_base)
        return run_policy(world, motion, MethodStrategy(checked.plan, HAND, obj), obj, HeldTest())


@pytest.mark.slow
@pytest.mark.parametrize("grasp", list(HumanGrasp), ids=lambda g: g.value)
def test_the_hand_alone_holds_the_default_object(grasp):
    pytest.importorskip("sapien")
    outcome = hand_alone_run(grasp)
    assert outcome.success, outcome.failure_reason
    assert outcome.held_after_lift and outcome.held_under_disturbance
