"""The KUKA KR 5 sixx R850 model: kinematics against the KR 5 spec (docs/robots/kuka.md),
limits and home pose. Contract, registration, generator and SAPIEN loading are
checked for every robot in test_robots_generic.py and test_registered_contracts.py."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from graspframe_kuka.description import HOME_Q, arm_description

ARM = arm_description()

# The KR 5 spec (docs/robots/kuka.md), copied here independently of the generator:
# alpha_{i-1} [deg], a_{i-1} [mm], d_i [mm], theta offset [deg], limits [deg], speed [deg/s].
ROBOTS_MD = (
    (0, 0, 335, 0, -170, 170, 375),
    (-90, 75, 0, 0, -190, 45, 300),
    (0, 365, 0, -90, -119, 165, 375),
    (-90, 90, 405, 0, -190, 190, 410),
    (90, 0, 0, 0, -120, 120, 410),
    (-90, 0, 80, 180, -358, 358, 660),
)
JOINT_NAMES = tuple(f"kr5_a{i}" for i in range(1, 7))

FK_TOL = 1e-3  # [m] the brief's tolerance for the published FK facts (the spec says "about")
EXACT_TOL = 1e-5  # [m], [rad]: URDF numbers are written with 6 significant digits
URDF_LIMIT_TOL = 1e-4  # [rad] 6 digits in the URDF; SAPIEN keeps limits to about 1e-4
DOWN_TOL = math.radians(1.0)  # [rad] "flange pointing down within 1 deg"


@pytest.fixture(scope="module")
def model():
    return pin.buildModelFromUrdf(str(ARM.model_path), False)


def _fk(model, q_deg) -> pin.Data:
    data = model.createData()
    pin.forwardKinematics(model, data, np.radians(np.asarray(q_deg, dtype=float)))
    pin.updateFramePlacements(model, data)
    return data


def _frame(model, data, name) -> pin.SE3:
    return data.oMf[model.getFrameId(name)]


def _axis_line(model, q_deg, joint_name):
    """(point, unit direction) of a revolute joint axis in the base frame; the direction is
    the angular velocity the joint causes."""
    data = model.createData()
    pin.computeJointJacobians(model, data, np.radians(np.asarray(q_deg, dtype=float)))
    joint_id = model.getJointId(joint_name)
    J = pin.getJointJacobian(model, data, joint_id, pin.LOCAL_WORLD_ALIGNED)
    return data.oMi[joint_id].translation, J[3:, model.joints[joint_id].idx_v]


def _distance_to_line(p, point, direction) -> float:
    return float(np.linalg.norm(np.cross(p - point, direction)))


def _dh_flange(q_rad) -> np.ndarray:
    """T_base_flange by Craig's modified DH of the KR 5 spec table, theta = A + offset."""
    T = np.eye(4)
    for (alpha, a, d, offset, *_), q in zip(ROBOTS_MD, q_rad, strict=True):
        ca, sa = math.cos(math.radians(alpha)), math.sin(math.radians(alpha))
        theta = q + math.radians(offset)
        ct, st = math.cos(theta), math.sin(theta)
        T = T @ np.array(
            [
                [ct, -st, 0, a / 1000],
                [st * ca, ct * ca, -sa, -sa * d / 1000],
                [st * sa, ct * sa, ca, ca * d / 1000],
                [0, 0, 0, 1],
            ]
        )
    return T


def test_robots_md_pose_wrist_and_flange(model):
    """KR 5 spec: wrist point about (480, 0, 790) mm, flange at x = 560, in KUKA's
    mechanical zero (A2 = -90, A3 = +90: upper arm up, forearm forward)."""
    mechanical_zero = (0, -90, 90, 0, 0, 0)
    data = _fk(model, mechanical_zero)
    wrist = _frame(model, data, "kr5_link_5").translation
    np.testing.assert_allclose(wrist, (0.480, 0.0, 0.790), atol=FK_TOL)
    # The wrist point is where the A4, A5 and A6 axes meet.
    for joint in ("kr5_a4", "kr5_a5", "kr5_a6"):
        assert _distance_to_line(wrist, *_axis_line(model, mechanical_zero, joint)) < EXACT_TOL
    flange = _frame(model, data, "kr5_flange")
    np.testing.assert_allclose(flange.translation, (0.560, 0.0, 0.790), atol=FK_TOL)
    np.testing.assert_allclose(flange.rotation[:, 2], (1.0, 0.0, 0.0), atol=EXACT_TOL)


def test_dh_zero_pose_is_the_stretched_arm(model):
    """All A_i = 0 is the zero of the DH table: upper arm and forearm forward."""
    data = _fk(model, (0,) * 6)
    np.testing.assert_allclose(
        _frame(model, data, "kr5_link_5").translation, (0.845, 0.0, 0.425), atol=FK_TOL
    )
    flange = _frame(model, data, "kr5_flange")
    np.testing.assert_allclose(flange.translation, (0.925, 0.0, 0.425), atol=FK_TOL)
    np.testing.assert_allclose(flange.rotation[:, 2], (1.0, 0.0, 0.0), atol=EXACT_TOL)


def test_urdf_joint_angles_are_kuka_axis_values(model):
    """At random configurations the URDF flange pose equals the DH table's with
    theta_i = A_i + offset_i: URDF angles are KUKA's A1..A6 and the flange is DH frame 6."""
    rng = np.random.default_rng(0)
    lower, upper = model.lowerPositionLimit, model.upperPositionLimit
    for _ in range(50):
        q = rng.uniform(lower, upper)
        data = _fk(model, np.degrees(q))
        expected = _dh_flange(q)
        flange = _frame(model, data, "kr5_flange")
        np.testing.assert_allclose(flange.translation, expected[:3, 3], atol=EXACT_TOL)
        np.testing.assert_allclose(flange.rotation, expected[:3, :3], atol=EXACT_TOL)


def test_axis_directions_follow_the_dh_table(model):
    """Stated sign convention, in the base frame at the zero pose."""
    expected = {
        "kr5_a1": (0, 0, 1),
        "kr5_a2": (0, 1, 0),
        "kr5_a3": (0, 1, 0),
        "kr5_a4": (1, 0, 0),
        "kr5_a5": (0, 1, 0),
        "kr5_a6": (1, 0, 0),
    }
    for joint, axis in expected.items():
        np.testing.assert_allclose(_axis_line(model, (0,) * 6, joint)[1], axis, atol=EXACT_TOL)


def test_limits_and_speeds_are_robots_md(model):
    assert ARM.joint_names == JOINT_NAMES
    for spec, row in zip(ARM.joints, ROBOTS_MD, strict=True):
        lower_deg, upper_deg, speed_deg_s = row[4:]
        assert spec.lower == pytest.approx(math.radians(lower_deg), abs=1e-12)
        assert spec.upper == pytest.approx(math.radians(upper_deg), abs=1e-12)
        assert spec.max_velocity == pytest.approx(math.radians(speed_deg_s), abs=1e-12)
        assert spec.max_velocity < spec.max_acceleration < spec.max_jerk < math.inf
        iq = model.joints[model.getJointId(spec.name)].idx_q
        assert model.lowerPositionLimit[iq] == pytest.approx(spec.lower, abs=URDF_LIMIT_TOL)
        assert model.upperPositionLimit[iq] == pytest.approx(spec.upper, abs=URDF_LIMIT_TOL)
        assert model.velocityLimit[iq] == pytest.approx(spec.max_velocity, abs=URDF_LIMIT_TOL)
        assert model.effortLimit[iq] == pytest.approx(spec.max_effort, rel=1e-5)


def test_mass_is_about_29_kg(model):
    total = sum(inertia.mass for inertia in model.inertias)
    assert total == pytest.approx(29.0, abs=0.1)  # the flange marker adds a token 1 g


def test_home_pose(model):
    """Flange straight down, 0.45-0.55 m in front of the base, 0.30-0.45 m high, at least
    10 deg from every limit and away from singularities."""
    margin = math.radians(10.0)
    for spec, q in zip(ARM.joints, HOME_Q, strict=True):
        assert spec.lower + margin <= q <= spec.upper - margin, spec.name
    q = np.asarray(HOME_Q)
    data = _fk(model, np.degrees(q))
    flange = _frame(model, data, "kr5_flange")
    down = float(flange.rotation[:, 2] @ (0.0, 0.0, -1.0))
    assert down >= math.cos(DOWN_TOL)
    x, y, z = flange.translation
    assert 0.45 <= math.hypot(x, y) <= 0.55 and x > 0.0
    assert 0.30 <= z <= 0.45
    # Smallest singular value of the 6x6 flange Jacobian: 0 at a singularity (it is 0 at
    # the zero pose, where A4 and A6 line up); 0.1 leaves a clear margin.
    pin.computeJointJacobians(model, data, q)
    J = pin.getFrameJacobian(model, data, model.getFrameId("kr5_flange"), pin.LOCAL_WORLD_ALIGNED)
    assert np.linalg.svd(J, compute_uv=False).min() > 0.1
