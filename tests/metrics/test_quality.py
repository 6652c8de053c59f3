"""Grasp quality (Ferrari-Canny epsilon, wrench-space volume) on textbook grasps."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from graspframe.common.errors import GraspframeError
from graspframe.metrics.quality import contact_wrenches, grasp_quality

R = 0.04  # [m] sphere / disc radius
MU = 0.5


def _rim(n_contacts: int, radius: float = R, z: float = 0.0):
    """Contacts evenly round a circle in the x-y plane, normals pointing to its centre."""
    angles = 2 * math.pi * np.arange(n_contacts) / n_contacts
    points = np.column_stack(
        [radius * np.cos(angles), radius * np.sin(angles), np.full_like(angles, z)]
    )
    return points, -points / np.linalg.norm(points, axis=1, keepdims=True)


def test_two_antipodal_contacts_on_a_sphere_close_in_force_but_not_against_every_torque():
    points, normals = _rim(2)
    force = grasp_quality(points, normals, MU, space="force", linf=True)
    assert force.force_closure and force.epsilon_l1 > 0 and force.epsilon_linf > 0
    # Two point contacts cannot resist a torque about the line through them.
    wrench = grasp_quality(points, normals, MU, torque_length=R, linf=True, edges=4)
    assert wrench.epsilon_l1 == 0.0 and wrench.epsilon_linf == 0.0
    assert not wrench.force_closure


def test_antipodal_force_epsilon_matches_the_friction_pyramid():
    """Two antipodal contacts along x: the L1 force space is a prism between x = -1 and
    x = +1 whose cross-section is the friction pyramid's polygon (circumradius mu), so
    the largest ball has the polygon's inradius, mu cos(pi / edges), when that is < 1."""
    points, normals = _rim(2)
    for edges in (4, 8, 16):
        q = grasp_quality(points, normals, MU, space="force", edges=edges)
        assert q.epsilon_l1 == pytest.approx(MU * math.cos(math.pi / edges), rel=1e-9)


def test_three_coplanar_contacts_on_a_disc_are_force_closure():
    points, normals = _rim(3)
    q = grasp_quality(points, normals, MU, torque_length=R, linf=True, edges=4)
    assert q.force_closure and q.epsilon_l1 > 0 and q.volume_l1 > 0
    assert q.epsilon_linf >= q.epsilon_l1 and q.volume_linf >= q.volume_l1
    # Without friction three rim contacts resist no force out of the plane.
    frictionless = grasp_quality(points, normals, 0.0, torque_length=R)
    assert frictionless.epsilon_l1 == 0.0 and frictionless.volume_l1 == 0.0


def test_more_friction_gives_a_better_grasp():
    points, normals = _rim(3)
    qualities = [
        grasp_quality(points, normals, mu, torque_length=R).epsilon_l1 for mu in (0.2, 0.5, 1.0)
    ]
    assert qualities == sorted(qualities) and qualities[0] > 0


def test_contacts_on_one_side_cannot_resist_a_pure_torque():
    """Three contacts all pushing along +z on one face of a box: no force closure."""
    points = np.array([[0.01, 0.0, 0.0], [-0.01, 0.01, 0.0], [-0.01, -0.01, 0.0]])
    normals = np.tile([0.0, 0.0, 1.0], (3, 1))
    q = grasp_quality(points, normals, MU, centre=(0, 0, 0.02), torque_length=0.02, linf=True)
    assert q.epsilon_l1 == 0.0 and q.epsilon_linf == 0.0 and not q.force_closure


def test_quality_is_unchanged_by_a_rigid_motion_of_the_whole_grasp():
    rng = np.random.default_rng(3)
    # A generic 4-contact grasp on a sphere (contacts off the rim, normals inward).
    directions = np.array([[1, 0.2, 0.3], [-1, 0.1, -0.2], [0.1, 1, -0.4], [0.2, -1, 0.5]])
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    # Contacts on a box-like object: normals not through the centre (every contact has
    # a lever arm across its normal).
    points = R * directions + np.array([0.0, 0.0, 0.01])
    normals = -directions
    centre = np.zeros(3)
    kwargs = {"torque_length": R, "edges": 4, "linf": True}
    base = grasp_quality(points, normals, MU, centre=centre, **kwargs)
    for _ in range(2):
        rotation = Rotation.random(random_state=rng).as_matrix()
        shift = rng.normal(size=3)
        moved = grasp_quality(
            points @ rotation.T + shift,
            normals @ rotation.T,
            MU,
            centre=rotation @ centre + shift,
            **kwargs,
        )
        assert moved.epsilon_l1 == pytest.approx(base.epsilon_l1, rel=1e-4)
        assert moved.epsilon_linf == pytest.approx(base.epsilon_linf, rel=1e-4)
        assert moved.volume_l1 == pytest.approx(base.volume_l1, rel=1e-4)
        assert moved.volume_linf == pytest.approx(base.volume_linf, rel=1e-4)
    assert base.force_closure


def test_wrenches_are_unit_normal_forces_with_torques_over_the_length():
    points, normals = _rim(2)
    w = contact_wrenches(points, normals, MU, torque_length=R, edges=6)
    assert w.shape == (2, 6, 6)
    np.testing.assert_allclose(
        w[..., :3] @ np.array([-1.0, 0.0, 0.0]), np.r_[np.ones(6), -np.ones(6)].reshape(2, 6)
    )
    np.testing.assert_allclose(np.linalg.norm(w[..., :3], axis=-1), math.hypot(1.0, MU))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"points": np.zeros((2, 3)), "normals": np.ones((1, 3))}, "one normal per contact"),
        ({"normals": np.zeros((2, 3))}, "non-zero"),
        ({"friction": -0.1}, "friction"),
        ({"torque_length": 0.0}, "torque_length"),
        ({"edges": 2}, "at least 3 edges"),
        ({"space": "torque"}, "unknown space"),
    ],
)
def test_bad_input_is_refused_with_a_clear_error(kwargs, message):
    points, normals = _rim(2)
    args = {"points": points, "normals": normals, "friction": MU, **kwargs}
    with pytest.raises(GraspframeError, match=message):
        grasp_quality(**args)
