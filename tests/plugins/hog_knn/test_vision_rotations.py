"""Rotation averaging (graspframe.vision.rotations): correct across the +-pi wrap."""

from __future__ import annotations

import numpy as np
import pytest
from graspframe_hog_knn.rotations import angle_deg, average_rotations
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from graspframe.common.errors import GraspframeError

unit_axes = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1)


def _R(axis, angle):
    axis = np.asarray(axis, float)
    return Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle).as_matrix()


@settings(max_examples=60, deadline=None)
@given(
    axis=unit_axes,
    spread=st.floats(0.01, 0.5),
    weight=st.floats(0.1, 10.0),
    offset=st.floats(-0.05, 0.05),
)
def test_average_of_rotations_straddling_pi(axis, spread, weight, offset):
    # Angles pi + offset +- spread about one axis: naive angle or Euler averaging lands
    # near 0 (the far side of the wrap); the true mean is the rotation by pi + offset.
    centre = np.pi + offset
    Rs = [_R(axis, centre - spread), _R(axis, centre + spread)]
    mean = average_rotations(Rs, [weight, weight])
    assert angle_deg(mean, _R(axis, centre)) < 1e-4


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_average_is_bi_invariant_and_sign_free(seed):
    rng = np.random.default_rng(seed)
    base = Rotation.random(random_state=seed).as_matrix()
    Rs = [base @ _R(rng.normal(size=3), rng.uniform(0, 0.4)) for _ in range(5)]
    w = rng.uniform(0.1, 1.0, 5)
    mean = average_rotations(Rs, w)
    G = Rotation.random(random_state=seed + 1).as_matrix()
    assert angle_deg(average_rotations([G @ R for R in Rs], w), G @ mean) < 1e-4
    assert angle_deg(average_rotations([R @ G for R in Rs], w), mean @ G) < 1e-4
    # Every input lies within 0.4 rad of `base`: so does the mean.
    assert angle_deg(mean, base) < np.degrees(0.4)


def test_weights_pull_the_mean():
    a, b = _R([0, 0, 1], 0.0), _R([0, 0, 1], 1.0)
    # Matrices compared directly: arccos resolves angles only to ~1e-8 rad near 0.
    np.testing.assert_allclose(average_rotations([a, b], [1.0, 0.0]), a, atol=1e-12)
    np.testing.assert_allclose(
        average_rotations([a, b], [1.0, 1.0]), _R([0, 0, 1], 0.5), atol=1e-12
    )


def test_bad_input_is_refused():
    with pytest.raises(GraspframeError):
        average_rotations(np.zeros((0, 3, 3)))
    with pytest.raises(GraspframeError):
        average_rotations([np.eye(3)], [-1.0])


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.integers(1, 10))
def test_average_is_the_top_eigenvector_of_the_weighted_quaternion_outer_products(seed, n):
    rng = np.random.default_rng(seed)
    base = Rotation.random(random_state=seed)
    rotations = base * Rotation.from_rotvec(rng.normal(scale=0.5, size=(n, 3)))
    w = rng.uniform(0.0, 1.0, n) + 1e-3
    quats = rotations.as_quat()
    _, vectors = np.linalg.eigh((quats * w[:, None]).T @ quats)
    expected = Rotation.from_quat(vectors[:, -1]).as_matrix()
    np.testing.assert_allclose(average_rotations(rotations.as_matrix(), w), expected, atol=1e-12)
