"""The KUKA LBR iiwa 14 R820 model: kinematics against the iiwa spec, limits, masses, home
pose. Contract, registration, generator and SAPIEN loading are checked for
every robot in test_robots_generic.py and test_registered_contracts.py."""

from __future__ import annotations

import math
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin
import pytest
from graspframe_kuka_iiwa14.description import HOME_Q, arm_description

ARM = arm_description()

# The iiwa spec (docs/robots/kuka_iiwa14.md), copied here independently of the generator.
LIMITS_DEG = (170, 120, 170, 120, 170, 120, 175)
SPEEDS_DEG_S = (85, 85, 100, 75, 130, 135, 135)
TORQUES_NM = (320, 320, 176, 176, 110, 40, 40)
MASSES_KG = (5, 4, 4, 3, 2.7, 1.7, 1.8, 0.3)  # base, link 1 .. link 7
JOINT_NAMES = tuple(f"iiwa_a{i}" for i in range(1, 8))
LINK_NAMES = ("iiwa_base", *(f"iiwa_link_{i}" for i in range(1, 8)))

FK_TOL = 1e-3  # [m] the brief's tolerance for the published FK facts
EXACT_TOL = 1e-6  # [m], [-]: offsets are exact in the URDF, axes are unit vectors
URDF_LIMIT_TOL = 1e-4  # [rad] 6 digits in the URDF; SAPIEN keeps limits to about 1e-4
DOWN_TOL = math.radians(1.0)  # [rad] "flange pointing down within 1 deg"


@pytest.fixture(scope="module")
def model():
    return pin.buildModelFromUrdf(str(ARM.model_path), False)


def _fk(model, q) -> pin.Data:
    data = model.createData()
    pin.forwardKinematics(model, data, np.asarray(q, dtype=float))
    pin.updateFramePlacements(model, data)
    return data


def _frame(model, data, name) -> pin.SE3:
    return data.oMf[model.getFrameId(name)]


def _joint_axis(model, q, joint_name) -> np.ndarray:
    """Unit axis of a revolute joint in the base frame: the angular velocity it causes."""
    data = model.createData()
    pin.computeJointJacobians(model, data, q)
    joint_id = model.getJointId(joint_name)
    J = pin.getJointJacobian(model, data, joint_id, pin.LOCAL_WORLD_ALIGNED)
    return J[3:, model.joints[joint_id].idx_v]


def test_zero_pose_link7_and_flange(model):
    data = _fk(model, np.zeros(7))
    np.testing.assert_allclose(
        _frame(model, data, "iiwa_link_7").translation, (0.0, 0.0, 1.261), atol=FK_TOL
    )
    flange = _frame(model, data, "iiwa_flange")
    np.testing.assert_allclose(flange.translation, (0.0, 0.0, 1.306), atol=FK_TOL)
    np.testing.assert_allclose(flange.rotation[:, 2], (0.0, 0.0, 1.0), atol=EXACT_TOL)


def test_zero_pose_matches_standard_dh(model):
    """Standard DH: d1 = 360 (A2 axis height), d3 = 420 further (A4), d5 = 400 (A6),
    d7 = 126 from A6 to the flange."""
    data = _fk(model, np.zeros(7))
    height = {j: data.oMi[model.getJointId(j)].translation for j in JOINT_NAMES}
    np.testing.assert_allclose(height["iiwa_a2"], (0, 0, 0.360), atol=FK_TOL)
    np.testing.assert_allclose(height["iiwa_a4"], (0, 0, 0.360 + 0.420), atol=FK_TOL)
    np.testing.assert_allclose(height["iiwa_a6"], (0, 0, 0.780 + 0.400), atol=FK_TOL)
    flange_z = _frame(model, data, "iiwa_flange").translation[2]
    assert flange_z - height["iiwa_a6"][2] == pytest.approx(0.126, abs=FK_TOL)


def test_axis_directions(model):
    """z / y alternation; A4 turns about -y (our convention), at the zero pose."""
    z, y = (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)
    expected = (z, y, z, (0.0, -1.0, 0.0), z, y, z)
    for joint, axis in zip(JOINT_NAMES, expected, strict=True):
        np.testing.assert_allclose(_joint_axis(model, np.zeros(7), joint), axis, atol=EXACT_TOL)


def test_limits_speeds_torques_are_robots_md(model):
    assert ARM.joint_names == JOINT_NAMES
    for spec, limit, speed, torque in zip(
        ARM.joints, LIMITS_DEG, SPEEDS_DEG_S, TORQUES_NM, strict=True
    ):
        assert spec.lower == pytest.approx(-math.radians(limit), abs=1e-12)
        assert spec.upper == pytest.approx(math.radians(limit), abs=1e-12)
        assert spec.max_velocity == pytest.approx(math.radians(speed), abs=1e-12)
        assert spec.max_effort == torque
        assert spec.max_velocity < spec.max_acceleration < spec.max_jerk < math.inf
        iq = model.joints[model.getJointId(spec.name)].idx_q
        assert model.lowerPositionLimit[iq] == pytest.approx(spec.lower, abs=URDF_LIMIT_TOL)
        assert model.upperPositionLimit[iq] == pytest.approx(spec.upper, abs=URDF_LIMIT_TOL)
        assert model.velocityLimit[iq] == pytest.approx(spec.max_velocity, abs=URDF_LIMIT_TOL)
        assert model.effortLimit[iq] == pytest.approx(torque, rel=1e-5)


def test_link_masses_are_robots_md():
    # Read the URDF itself: Pinocchio merges the flange marker's token mass into link 7.
    root = ElementTree.parse(ARM.model_path).getroot()
    masses = {
        link.get("name"): float(link.find("inertial/mass").get("value"))
        for link in root.iter("link")
    }
    assert [masses[name] for name in LINK_NAMES] == pytest.approx(MASSES_KG, abs=1e-9)


def test_home_pose(model):
    """Flange straight down, 0.45-0.55 m in front of the base, 0.30-0.45 m high, at least
    15 deg from every limit and away from singularities."""
    margin = math.radians(15.0)
    for spec, q in zip(ARM.joints, HOME_Q, strict=True):
        assert spec.lower + margin <= q <= spec.upper - margin, spec.name
    q = np.asarray(HOME_Q)
    data = _fk(model, q)
    flange = _frame(model, data, "iiwa_flange")
    down = float(flange.rotation[:, 2] @ (0.0, 0.0, -1.0))
    assert down >= math.cos(DOWN_TOL)
    x, y, z = flange.translation
    assert 0.45 <= math.hypot(x, y) <= 0.55 and x > 0.0
    assert 0.30 <= z <= 0.45
    # Smallest singular value of the 6x7 flange Jacobian: 0 at a singularity (as at the
    # zero pose, where A1/A3/A5/A7 line up); 0.1 leaves a clear margin.
    pin.computeJointJacobians(model, data, q)
    J = pin.getFrameJacobian(model, data, model.getFrameId("iiwa_flange"), pin.LOCAL_WORLD_ALIGNED)
    assert np.linalg.svd(J, compute_uv=False).min() > 0.1
