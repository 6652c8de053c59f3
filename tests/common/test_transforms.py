"""Property tests for the pose and rotation conventions (fixed seeds via hypothesis settings)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from graspframe.common.errors import GraspframeError
from graspframe.common.transforms import (
    R_from_axis_angle,
    R_from_quat_wxyz,
    R_from_quat_xyzw,
    R_from_rpy,
    as_pose,
    inv_T,
    make_T,
    quat_wxyz_from_R,
    quat_xyzw_from_R,
    rotation_angle,
    rpy_from_R,
    transform_points,
)

seeds = st.integers(min_value=0, max_value=2**32 - 1)


def random_T(seed: int):
    rng = np.random.default_rng(seed)
    return make_T(Rotation.random(random_state=rng).as_matrix(), rng.uniform(-1, 1, 3))


@settings(max_examples=100, derandomize=True)
@given(seeds, seeds)
def test_compose_and_inverse(seed_a, seed_b):
    T_a_b, T_b_c = random_T(seed_a), random_T(seed_b)
    T_a_c = T_a_b @ T_b_c
    np.testing.assert_allclose(inv_T(T_a_c), np.linalg.inv(T_a_c), atol=1e-12)
    np.testing.assert_allclose(T_a_b @ inv_T(T_a_b), np.eye(4), atol=1e-12)
    p_c = np.array([0.1, -0.2, 0.3])
    np.testing.assert_allclose(
        transform_points(T_a_c, p_c), transform_points(T_a_b, transform_points(T_b_c, p_c))
    )


@settings(max_examples=100, derandomize=True)
@given(seeds)
def test_quaternion_orders_round_trip_and_sign_is_irrelevant(seed):
    R = random_T(seed)[:3, :3]
    quat_wxyz = quat_wxyz_from_R(R)
    np.testing.assert_allclose(np.roll(quat_xyzw_from_R(R), 1), quat_wxyz)  # same order, w first
    np.testing.assert_allclose(R_from_quat_wxyz(quat_wxyz), R, atol=1e-12)
    np.testing.assert_allclose(R_from_quat_wxyz(-quat_wxyz), R, atol=1e-12)
    np.testing.assert_allclose(R_from_quat_xyzw(quat_xyzw_from_R(R)), R, atol=1e-12)


def test_quaternion_component_order():
    R = R_from_rpy(0.0, 0.0, np.pi / 2)  # 90 deg about z
    s = np.sqrt(0.5)
    np.testing.assert_allclose(quat_wxyz_from_R(R), [s, 0, 0, s], atol=1e-12)
    np.testing.assert_allclose(quat_xyzw_from_R(R), [0, 0, s, s], atol=1e-12)


@settings(max_examples=100, derandomize=True)
@given(seeds)
def test_rpy_round_trip_and_rotation_angle(seed):
    R = random_T(seed)[:3, :3]
    np.testing.assert_allclose(R_from_rpy(*rpy_from_R(R)), R, atol=1e-9)
    assert rotation_angle(R, R) == pytest.approx(0.0, abs=1e-6)
    R_turn = R @ R_from_rpy(0.3, 0.0, 0.0)
    assert rotation_angle(R, R_turn) == pytest.approx(0.3, abs=1e-9)


def test_axis_angle_turns_about_the_axis_of_any_length():
    R = R_from_axis_angle([0.0, 0.0, 2.0], np.pi / 2)
    np.testing.assert_allclose(R @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(R, R_from_rpy(0.0, 0.0, np.pi / 2), atol=1e-12)


def test_as_pose_rejects_non_rigid_transforms():
    with pytest.raises(GraspframeError, match="4x4"):
        as_pose(np.eye(3))
    scaled = np.eye(4)
    scaled[0, 0] = 2.0
    with pytest.raises(GraspframeError, match="not a proper rotation"):
        as_pose(scaled, "T_world_object")
    mirrored = np.diag([1.0, 1.0, -1.0, 1.0])
    with pytest.raises(GraspframeError, match="not a proper rotation"):
        as_pose(mirrored)
