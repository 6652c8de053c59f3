"""The Barrett BH8-280 model: geometry against the published numbers (Barrett BH8-series
manual, docs/robots/barrett.md), couplings, frames, preshapes, and grasps that hold.

Positions come from Pinocchio forward kinematics of the shipped URDF. Tolerances:
- 0.5 mm on positions taken straight from the published numbers: the URDF stores 6
  significant digits, so anything above ~1 um is a modelling error, not rounding.
- 1 mm on delta: the description keeps it to 0.1 mm.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from graspframe_barrett.description import BARRETT, DISTAL, PROXIMAL, SPREAD, hand_q

from graspframe.common.grasps import PALM, HumanGrasp, Preshape
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.testing import closing_problems

MM = 1e-3
DEG = math.pi / 180.0
POSITION_TOL = 0.5 * MM
FINGERS = (1, 2, 3)


@pytest.fixture(scope="module")
def fk():
    """fk(q_by_joint, mimic=False) -> Pinocchio data after framesForwardKinematics.

    With mimic=False every URDF joint is free (bh_spread_2 must be given to move); with
    mimic=True bh_spread_2 follows bh_spread_1 as the URDF's <mimic> says."""
    models = {m: pin.buildModelFromUrdf(str(BARRETT.model_path), m) for m in (False, True)}

    def run(q_by_joint, mimic=False):
        model = models[mimic]
        data = model.createData()
        q = pin.neutral(model)
        for name, value in q_by_joint.items():
            joint = model.joints[model.getJointId(name)]
            assert joint.shortname() != "JointModelMimic", f"{name} is a mimic follower"
            q[joint.idx_q] = value
        pin.framesForwardKinematics(model, data, q)
        return model, data

    return run


def frame_position(model, data, name: str) -> np.ndarray:
    return data.oMf[model.getFrameId(name)].translation.copy()


def joint_placement(model, data, name: str) -> pin.SE3:
    return data.oMi[model.getJointId(name)]


def tips(fk, q_by_joint) -> dict[int, np.ndarray]:
    model, data = fk(q_by_joint, mimic=True)
    return {f: frame_position(model, data, f"bh_f{f}_tip") for f in FINGERS}


# --- SAPIEN ----------------------------------------------------------------------------


def test_sapien_enforces_the_spread_mimic_and_open_preshapes_do_not_penetrate():
    sapien = pytest.importorskip("sapien")
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(1 / 500)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    art = loader.load(str(BARRETT.model_path))
    joints = {j.name: j for j in art.get_active_joints()}
    gains = BARRETT.drive
    for name in BARRETT.joint_names:  # bh_spread_2 gets no drive: the mimic moves it
        joints[name].set_drive_property(gains.stiffness, gains.damping, gains.force_limit)
    preshape = BARRETT.preshape(Preshape.PRECISION_DISC)
    for name, value in preshape.open_q.items():
        joints[name].set_drive_target(value)
    for _ in range(1000):  # 2 s
        scene.step()
    q = dict(zip(joints, art.get_qpos(), strict=True))
    # Settles within 1 deg of the 60 deg target (gravity on the fingers, PD drive).
    assert q[SPREAD] == pytest.approx(preshape.open_q[SPREAD], abs=1 * DEG)
    assert q["bh_spread_2"] == pytest.approx(q[SPREAD], abs=0.1 * DEG)
    # PhysX reports shape pairs within its contact offset; none may overlap or push.
    for contact in scene.get_contacts():
        names = [body.entity.name for body in contact.bodies]
        for point in contact.points:
            assert point.separation > -0.5 * MM, f"{names} penetrate"
            assert np.linalg.norm(point.impulse) < 1e-6, f"{names} push each other"


# --- geometry against the published numbers ---------------------------------------


def test_flexion_axes_at_spread_zero(fk):
    model, data = fk({})
    expected_mm = {1: (25, 50, 75.4), 2: (-25, 50, 75.4), 3: (0, -50, 75.4)}
    for finger, xyz_mm in expected_mm.items():
        placement = joint_placement(model, data, f"bh_f{finger}_prox")
        np.testing.assert_allclose(placement.translation, np.array(xyz_mm) * MM, atol=POSITION_TOL)
        # The flexion axis (joint x axis) is parallel to the base x axis.
        assert abs(placement.rotation[:, 0] @ [1.0, 0.0, 0.0]) == pytest.approx(1.0, abs=1e-9)


def test_spread_axes(fk):
    model, data = fk({})
    for name, x_mm, axis_z in (("bh_spread_1", 25, -1.0), ("bh_spread_2", -25, 1.0)):
        placement = joint_placement(model, data, name)
        np.testing.assert_allclose(
            placement.translation, np.array([x_mm, 0, 41.5]) * MM, atol=POSITION_TOL
        )
        # Joint axis in the base frame: the angular part of the joint's own Jacobian column.
        q = pin.neutral(model)
        pin.computeJointJacobians(model, data, q)
        J = pin.getJointJacobian(
            model, data, model.getJointId(name), pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )
        column = model.joints[model.getJointId(name)].idx_v
        np.testing.assert_allclose(J[3:, column], [0.0, 0.0, axis_z], atol=1e-9)


def test_finger_segment_lengths(fk):
    """Flexion axis to distal joint 69.9 mm, distal joint to fingertip 50 mm; with the
    distal joint turned back by its 42 deg rest angle the finger is straight: 119.9 mm."""
    straight = {name: -42 * DEG for name in DISTAL}  # outside the limits, fine for FK
    model, data = fk({**straight, "bh_spread_2": 0.0})
    for finger in FINGERS:
        knuckle = joint_placement(model, data, f"bh_f{finger}_prox").translation
        distal = joint_placement(model, data, f"bh_f{finger}_dist").translation
        tip = frame_position(model, data, f"bh_f{finger}_tip")
        assert np.linalg.norm(distal - knuckle) == pytest.approx(69.9 * MM, abs=POSITION_TOL)
        assert np.linalg.norm(tip - distal) == pytest.approx(50 * MM, abs=POSITION_TOL)
        assert np.linalg.norm(tip - knuckle) == pytest.approx(119.9 * MM, abs=POSITION_TOL)


def test_distal_rests_42_degrees_bent(fk):
    model, data = fk({})
    for finger in FINGERS:
        knuckle = joint_placement(model, data, f"bh_f{finger}_prox").translation
        distal = joint_placement(model, data, f"bh_f{finger}_dist").translation
        tip = frame_position(model, data, f"bh_f{finger}_tip")
        a, b = distal - knuckle, tip - distal
        angle = math.acos(a @ b / np.linalg.norm(a) / np.linalg.norm(b))
        assert angle == pytest.approx(42 * DEG, abs=0.01 * DEG)
        # ... bent upwards, towards closing: the tip rises above the flat proximal link.
        assert tip[2] > distal[2] + 30 * MM


def test_flexion_zero_is_flat_and_positive_flexion_curls_towards_the_palm(fk):
    flat = tips(fk, hand_q(0, 0))
    upright = hand_q(0, 90)
    model, data = fk({**upright, "bh_spread_2": 0.0})
    for finger in FINGERS:
        knuckle = joint_placement(model, data, f"bh_f{finger}_prox").translation
        distal = joint_placement(model, data, f"bh_f{finger}_dist").translation
        # 90 deg: proximal link upright along the palm normal.
        np.testing.assert_allclose(distal - knuckle, [0, 0, 69.9 * MM], atol=POSITION_TOL)
        # 0 deg: the fingertip lies outside the knuckle, away from the palm axis (y = 0).
        assert abs(flat[finger][1]) > abs(knuckle[1]) + 100 * MM
    # Curling: fingers 1-2 tips move to -y, finger 3's to +y, as flexion grows.
    for a, b in ((60, 90), (90, 120)):
        tips_a, tips_b = tips(fk, hand_q(0, a)), tips(fk, hand_q(0, b))
        assert tips_b[1][1] < tips_a[1][1] and tips_b[2][1] < tips_a[2][1]
        assert tips_b[3][1] > tips_a[3][1]


def test_spread_carries_fingers_1_and_2_apart_towards_finger_3(fk):
    def knuckles(spread_deg):
        model, data = fk({SPREAD: spread_deg * DEG}, mimic=True)
        return {f: joint_placement(model, data, f"bh_f{f}_prox").translation for f in (1, 2)}

    at_90, at_180 = knuckles(90), knuckles(180)
    np.testing.assert_allclose(at_90[1], np.array([75, 0, 75.4]) * MM, atol=POSITION_TOL)
    np.testing.assert_allclose(at_90[2], np.array([-75, 0, 75.4]) * MM, atol=POSITION_TOL)
    # At 180 deg they stand beside finger 3 at y = -50.
    np.testing.assert_allclose(at_180[1], np.array([25, -50, 75.4]) * MM, atol=POSITION_TOL)
    np.testing.assert_allclose(at_180[2], np.array([-25, -50, 75.4]) * MM, atol=POSITION_TOL)


@pytest.mark.parametrize("spread_deg", [0, 30, 60, 120, 180])
def test_spread_mimic_makes_finger_2_mirror_finger_1(fk, spread_deg):
    """Pinocchio with mimic: finger 2 is finger 1 mirrored in the y-z plane (x -> -x)."""
    q = hand_q(spread_deg, 50)
    model, data = fk(q, mimic=True)
    assert model.nq == 7  # the follower adds no configuration variable
    mirror = np.array([-1.0, 1.0, 1.0])
    for part in ("bh_f{}_prox_link", "bh_f{}_dist_link", "bh_f{}_tip"):
        p1 = frame_position(model, data, part.format(1))
        p2 = frame_position(model, data, part.format(2))
        np.testing.assert_allclose(p2, mirror * p1, atol=1e-9)


def angle_around_palm_axis_deg(p) -> float:
    return math.degrees(math.atan2(p[1], p[0]))


def test_spread_60_turns_the_closing_planes_120_degrees_apart(fk):
    """At spread 60 deg each finger closes along a horizontal direction 120 deg from the
    others' (the fingertip displacement between two flexion angles)."""
    before, after = tips(fk, hand_q(60, 30)), tips(fk, hand_q(60, 60))
    angles = sorted(angle_around_palm_axis_deg(after[f] - before[f]) for f in FINGERS)
    gaps = np.diff([*angles, angles[0] + 360.0])
    np.testing.assert_allclose(gaps, 120.0, atol=0.01)


def test_spread_60_puts_the_open_fingertips_about_120_degrees_apart(fk):
    # +-10 deg: the closing planes meet 14.4 mm from the palm axis (towards finger 3), not
    # on it, so seen from the palm axis the tips of the open hand sit at 116/128/116 deg.
    t = tips(fk, hand_q(60, 0))
    angles = sorted(angle_around_palm_axis_deg(t[f]) for f in FINGERS)
    gaps = np.diff([*angles, angles[0] + 360.0])
    np.testing.assert_allclose(gaps, 120.0, atol=10.0)


def test_mass():
    model = pin.buildModelFromUrdf(str(BARRETT.model_path), False)
    total = sum(inertia.mass for inertia in model.inertias)
    # 1.2 kg (Barrett BH8-280 specifications) plus four marker links at 1 g each.
    assert total == pytest.approx(1.2, abs=0.01)


# --- palm frame and palm pad -----------------------------------------------------------


def test_palm_frame_pose(fk):
    model, data = fk({})
    T_base_palm = data.oMf[model.getFrameId(BARRETT.palm_frame)]
    # Origin at the palm surface centre, Dw = 84 mm from the flange (BH8-series manual).
    np.testing.assert_allclose(T_base_palm.translation, [0, 0, 84 * MM], atol=POSITION_TOL)
    R = T_base_palm.rotation
    # 1e-5: the URDF writes angles to 6 significant digits (pi/2 -> 1.5708).
    np.testing.assert_allclose(R[:, 2], [0, 0, 1], atol=1e-5)  # out of the palm
    np.testing.assert_allclose(R[:, 0], [0, 1, 0], atol=1e-5)  # finger 3 -> fingers 1-2
    np.testing.assert_allclose(R[:, 1], np.cross(R[:, 2], R[:, 0]), atol=1e-9)


def test_palm_frame_probes():
    collision = CollisionModel(model_of(BARRETT))
    T_base_palm = collision.T_root_frame(BARRETT.palm_frame)
    origin, z_axis = T_base_palm[:3, 3], T_base_palm[:3, 2]
    assert collision.links_containing(origin + 0.02 * z_axis) == []
    assert "bh_base" in collision.links_containing(origin - 0.01 * z_axis)
    # The pad is the palm surface: just under the frame origin is the pad, just above is air.
    assert collision.links_containing(origin - 0.5 * MM * z_axis) == [BARRETT.palm_sensor_link]
    assert collision.links_containing(origin + 0.5 * MM * z_axis) == []


def test_palm_pad_spans_the_published_area():
    collision = CollisionModel(model_of(BARRETT))
    T_base_palm = collision.T_root_frame(BARRETT.palm_frame)
    below = T_base_palm[:3, 3] - 1 * MM * T_base_palm[:3, 2]
    pad = BARRETT.palm_sensor_link
    for x_mm, y_mm, inside in ((37, 21, True), (-37, -21, True), (39, 0, False), (0, 22.5, False)):
        p = below + np.array([x_mm, y_mm, 0.0]) * MM
        assert (pad in collision.links_containing(p)) is inside, (x_mm, y_mm)
    assert pad in BARRETT.real_fingers[PALM]


# --- description: couplings, joints, preshapes -----------------------------------------


def test_driven_joints_exclude_the_mimic_follower():
    assert BARRETT.joint_names == (SPREAD, *PROXIMAL, *DISTAL)
    assert "bh_spread_2" not in BARRETT.joint_names


def test_couplings():
    by_follower = {c.follower: c for c in BARRETT.couplings}
    spread = by_follower["bh_spread_2"]
    assert (spread.leader, spread.multiplier, spread.in_model) == (SPREAD, 1.0, True)
    for prox, dist in zip(PROXIMAL, DISTAL, strict=True):
        c = by_follower[dist]
        assert c.leader == prox
        assert c.multiplier == pytest.approx(1 / 3)
        assert c.in_model is False  # TorqueSwitch: the controller enforces it


def test_urdf_mimic_is_only_the_spread():
    text = BARRETT.model_path.read_text()
    assert text.count("<mimic ") == 1
    assert '<mimic joint="bh_spread_1" multiplier="1" offset="0"/>' in text


def test_preshapes_set_every_joint_and_follow_the_distal_coupling():
    for preshape in BARRETT.preshapes.values():
        for q in (preshape.open_q, preshape.closed_q):
            assert set(q) == set(BARRETT.joint_names)
            for prox, dist in zip(PROXIMAL, DISTAL, strict=True):
                assert q[dist] == pytest.approx(q[prox] / 3)
                assert BARRETT.joint(dist).contains(q[dist])


def test_mapping_table():
    expected = {
        HumanGrasp.LARGE_DIAMETER: Preshape.WRAP,
        HumanGrasp.SMALL_DIAMETER: Preshape.WRAP,
        HumanGrasp.ABDUCTED_THUMB: Preshape.PRECISION,
        HumanGrasp.PINCH: Preshape.PRECISION,
        HumanGrasp.POWER_SPHERE: Preshape.PRECISION_DISC,
        HumanGrasp.PRECISION_DISC: Preshape.PRECISION_DISC,
    }
    assert {g: BARRETT.preshape_for(g).name for g in HumanGrasp} == expected


@pytest.mark.parametrize("name", list(Preshape)[:3])
def test_delta_is_the_fingertip_height_above_the_palm(fk, name):
    preshape = BARRETT.preshape(name)
    model, data = fk(preshape.open_q, mimic=True)
    T_base_palm = data.oMf[model.getFrameId(BARRETT.palm_frame)]
    heights = [T_base_palm.actInv(frame_position(model, data, f"bh_f{f}_tip"))[2] for f in FINGERS]
    assert preshape.delta == pytest.approx(max(heights), abs=1 * MM)


def test_wrap_opens_wide():
    t = tips_of(Preshape.WRAP, "open")
    # Fingertips more than 15 cm apart: the 10 cm can (125 % Large Diameter object)
    # passes between them with room for a 2.5 cm position error on either side.
    assert t[1][1] - t[3][1] > 0.15


def test_precision_opens_to_a_small_aperture_and_closes_past_the_meeting_point():
    t_open = tips_of(Preshape.PRECISION, "open")
    aperture = t_open[1][1] - t_open[3][1]
    # Wide enough for the 7.5 cm cylinder (125 % Abducted Thumb object) to pass between
    # the open fingertips, less than two thirds of the wrap's aperture.
    assert 0.11 <= aperture <= 0.125
    t_wrap = tips_of(Preshape.WRAP, "open")
    assert aperture < 2 / 3 * (t_wrap[1][1] - t_wrap[3][1])
    t_closed = tips_of(Preshape.PRECISION, "closed")
    assert t_closed[1][1] < t_closed[3][1]  # the tips have passed each other in free space


def test_precision_disc_spreads_to_about_120_degrees():
    spread = BARRETT.preshape(Preshape.PRECISION_DISC).open_q[SPREAD]
    assert spread == pytest.approx(60 * DEG, abs=5 * DEG)


def test_open_preshapes_are_free_of_self_collision():
    collision = CollisionModel(model_of(BARRETT))
    for q in (hand_q(0, 0), *(p.open_q for p in BARRETT.preshapes.values())):
        collision.place(BARRETT.with_model_followers(q))
        assert collision.colliding_links() == [], q


# --- where the object sits, which fingers oppose, and grasps that hold ------------------


def test_closing_brings_the_opposed_fingers_together():
    assert closing_problems(BARRETT) == []
    for preshape in BARRETT.preshapes.values():
        assert set(preshape.opposed) == {("finger_1", "finger_3"), ("finger_2", "finger_3")}


def test_every_preshape_declares_where_the_object_sits():
    for preshape in BARRETT.preshapes.values():
        assert preshape.design_object is not None, preshape.name
        assert preshape.grasp_center_palm == preshape.design_object.centre
    wrap = BARRETT.preshape(Preshape.WRAP)
    # Volar: the design object rests on the palm, nearer finger 3 (palm -x).
    assert wrap.design_object.centre[2] == pytest.approx(wrap.design_object.radius)
    assert wrap.design_object.centre[0] == pytest.approx(-0.015)
    # Precision: between finger 1 (palm y -36 .. -14 mm) and finger 3 (-11 .. 11 mm), not
    # in the 28 mm gap between fingers 1 and 2 that a 25 mm block falls through.
    assert BARRETT.preshape(Preshape.PRECISION).grasp_center_palm[1] == pytest.approx(-0.0125)


def test_rolls_close_square_to_the_human_postures_cylinders():
    """The roll turns the closing direction (palm x) perpendicular to the cylinder axis of
    the human posture that uses the preshape most: the Small Diameter handle for the wrap,
    the Abducted Thumb cylinder for the precision grasp."""
    from graspframe.plugin_system.registry import default_registry

    human = default_registry().get_hand("human")
    for grasp, preshape in (
        (HumanGrasp.SMALL_DIAMETER, Preshape.WRAP),
        (HumanGrasp.ABDUCTED_THUMB, Preshape.PRECISION),
    ):
        axis = np.asarray(human.preshape_for(grasp).design_object.axis)
        roll = BARRETT.preshape(preshape).roll
        closing = np.array([math.cos(roll), math.sin(roll), 0.0])  # robot palm x, human frame
        assert abs(closing @ axis) < math.sin(1 * DEG), grasp


def test_precision_disc_fingertips_reach_an_object_together():
    """Finger 3 opens 22 deg further than fingers 1 and 2; closing at equal speeds, the
    three fingertips stay equally far (within 3 mm) from the line where the closing planes
    meet, which is where the object's centre sits, so any object 6-22 cm across is
    reached by all three at once."""
    preshape = BARRETT.preshape(Preshape.PRECISION_DISC)
    offset = preshape.open_q[PROXIMAL[0]] - preshape.open_q[PROXIMAL[2]]
    assert offset == pytest.approx(22 * DEG)
    centre = np.asarray(preshape.grasp_center_palm)
    model = pin.buildModelFromUrdf(str(BARRETT.model_path), True)
    data = model.createData()
    palm_id = model.getFrameId(BARRETT.palm_frame)
    for step_deg in range(18, 55, 6):
        q = BARRETT.with_model_followers(dict(preshape.open_q))
        for prox, dist in zip(PROXIMAL, DISTAL, strict=True):
            q[prox] += step_deg * DEG
            q[dist] = q[prox] / 3
        config = pin.neutral(model)
        for joint_name, value in q.items():
            joint = model.joints[model.getJointId(joint_name)]
            if joint.shortname() != "JointModelMimic":
                config[joint.idx_q] = value
        pin.framesForwardKinematics(model, data, config)
        T_palm = data.oMf[palm_id]
        reach = [
            np.linalg.norm(
                (T_palm.actInv(frame_position(model, data, f"bh_f{f}_tip")) - centre)[:2]
            )
            for f in FINGERS
        ]
        assert max(reach) - min(reach) < 3 * MM, (step_deg, reach)
        assert min(reach) > 0.035 and max(reach) < 0.115


@pytest.mark.slow
@pytest.mark.parametrize("grasp", list(HumanGrasp), ids=lambda g: g.value)
def test_hand_alone_holds_each_grasp_on_its_default_object(grasp, tmp_path):
    """`graspframe run --hand barrett --grasp <grasp> --mount floating`: the hand alone on
    a free base, placed from the human reference grasp, holds the grasp's own object
    through the lift and the disturbance test (docs/robots/barrett.md, "Held")."""
    pytest.importorskip("sapien")
    from graspframe.common.defaults import MOUNT_FLOATING
    from graspframe.run.request import RunRequest
    from graspframe.run.runner import run_grasp

    request = RunRequest(
        hand="barrett", grasp=grasp, mount=MOUNT_FLOATING, record=False, out_root=str(tmp_path)
    )
    outcome = run_grasp(request).to_json()["outcome"]
    assert outcome["success"], outcome["failure_reason"]
    assert outcome["held_after_lift"] and outcome["held_under_disturbance"]


def tips_of(name: Preshape, which: str) -> dict[int, np.ndarray]:
    preshape = BARRETT.preshape(name)
    q = preshape.open_q if which == "open" else preshape.closed_q
    model = pin.buildModelFromUrdf(str(BARRETT.model_path), True)
    data = model.createData()
    config = pin.neutral(model)
    for joint_name, value in q.items():
        config[model.joints[model.getJointId(joint_name)].idx_q] = value
    pin.framesForwardKinematics(model, data, config)
    return {f: frame_position(model, data, f"bh_f{f}_tip") for f in FINGERS}
