"""Averaging rotations: the weighted chordal L2 mean via quaternions (Markley et al.,
"Averaging Quaternions", J. Guidance 2007), as computed by scipy's `Rotation.mean`.

The mean maximises sum_i w_i (q_i . q)^2 over unit quaternions q: the eigenvector of the
largest eigenvalue of M = sum_i w_i q_i q_i^T. The outer product is the same for q and
-q, so the result does not depend on quaternion signs, and rotations on either side of
the +-pi wrap average correctly (unlike Euler angles or naive quaternion sums).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from graspframe.common.errors import GraspframeError
from graspframe.common.transforms import rotation_angle


def average_rotations(rotations: ArrayLike, weights: ArrayLike | None = None) -> NDArray:
    """Weighted mean of rotation matrices (N, 3, 3) with weights (N,) >= 0 -> (3, 3)."""
    Rs = np.asarray(rotations, dtype=float).reshape(-1, 3, 3)
    if len(Rs) == 0:
        raise GraspframeError("cannot average an empty set of rotations")
    w = np.ones(len(Rs)) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != (len(Rs),) or np.any(w < 0) or not w.sum() > 0:
        raise GraspframeError("rotation weights must be N values >= 0 with a positive sum")
    return Rotation.from_matrix(Rs).mean(weights=w).as_matrix()


def angle_deg(R_a: ArrayLike, R_b: ArrayLike) -> float:
    """Angle between two rotations [deg]."""
    return float(np.degrees(rotation_angle(R_a, R_b)))
