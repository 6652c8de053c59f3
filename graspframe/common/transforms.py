"""Poses and rotations: the one module that converts between representations.

Convention: `T_a_b` is the 4x4 homogeneous pose of frame b expressed in frame a (it maps
points given in b into a), so poses compose by cancelling inner letters:
`T_world_palm = T_world_flange @ T_flange_palm`. Quaternions are always named by their
component order: `quat_wxyz` (SAPIEN) or `quat_xyzw` (Pinocchio, rerun, scipy).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from graspframe.common.errors import InputError

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

Mat4 = NDArray[np.float64]
Mat3 = NDArray[np.float64]
Vec3 = NDArray[np.float64]


def _rotation() -> type[Rotation]:
    """scipy's Rotation, imported at the first conversion: scipy.spatial takes about
    0.3 s to import, and the hands and arms are described without it (a mistyped name on
    the command line is answered before it loads)."""
    from scipy.spatial.transform import Rotation

    return Rotation


def make_T(R: ArrayLike | None = None, p: ArrayLike | None = None) -> Mat4:
    """Homogeneous pose from a rotation matrix R (3x3) and a translation p (3,) [m]."""
    T = np.eye(4)
    if R is not None:
        T[:3, :3] = np.asarray(R, dtype=float).reshape(3, 3)
    if p is not None:
        T[:3, 3] = np.asarray(p, dtype=float).reshape(3)
    return T


def inv_T(T_a_b: ArrayLike) -> Mat4:
    """T_b_a from T_a_b, using the rotation's transpose (no general matrix inverse)."""
    T_a_b = np.asarray(T_a_b, dtype=float)
    R = T_a_b[:3, :3]
    T_b_a = np.eye(4)
    T_b_a[:3, :3] = R.T
    T_b_a[:3, 3] = -R.T @ T_a_b[:3, 3]
    return T_b_a


def transform_points(T_a_b: ArrayLike, p_b: ArrayLike) -> NDArray[np.float64]:
    """Points p_b (N,3) or (3,) given in frame b, expressed in frame a."""
    T_a_b = np.asarray(T_a_b, dtype=float)
    p_b = np.asarray(p_b, dtype=float)
    return p_b @ T_a_b[:3, :3].T + T_a_b[:3, 3]


def rotate_vectors(T_or_R_a_b: ArrayLike, v_b: ArrayLike) -> NDArray[np.float64]:
    """Direction vectors v_b (N,3) or (3,) rotated into frame a (no translation)."""
    M = np.asarray(T_or_R_a_b, dtype=float)
    return np.asarray(v_b, dtype=float) @ M[:3, :3].T


def R_from_quat_xyzw(quat_xyzw: ArrayLike) -> Mat3:
    return _rotation().from_quat(np.asarray(quat_xyzw, dtype=float)).as_matrix()


def R_from_quat_wxyz(quat_wxyz: ArrayLike) -> Mat3:
    return _rotation().from_quat(np.asarray(quat_wxyz, dtype=float), scalar_first=True).as_matrix()


def quat_xyzw_from_R(R: ArrayLike) -> NDArray[np.float64]:
    return _rotation().from_matrix(np.asarray(R, dtype=float)).as_quat()


def quat_wxyz_from_R(R: ArrayLike) -> NDArray[np.float64]:
    return _rotation().from_matrix(np.asarray(R, dtype=float)).as_quat(scalar_first=True)


def R_from_rpy(roll: float, pitch: float, yaw: float) -> Mat3:
    """URDF convention: fixed-axis X-Y-Z rotations, R = Rz(yaw) Ry(pitch) Rx(roll)."""
    return _rotation().from_euler("xyz", [roll, pitch, yaw]).as_matrix()


def rpy_from_R(R: ArrayLike) -> NDArray[np.float64]:
    """Inverse of `R_from_rpy`: (roll, pitch, yaw) [rad]. At pitch +-90 deg (gimbal lock)
    roll and yaw turn about the same axis: yaw is 0 and roll takes the whole turn."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Gimbal lock detected")
        return _rotation().from_matrix(np.asarray(R, dtype=float)).as_euler("xyz")


def R_from_axis_angle(axis: ArrayLike, angle: float) -> Mat3:
    """The rotation by `angle` [rad] about `axis` (any non-zero length)."""
    axis = np.asarray(axis, dtype=float)
    return _rotation().from_rotvec(axis / np.linalg.norm(axis) * angle).as_matrix()


def rotation_angle(R_a: ArrayLike, R_b: ArrayLike) -> float:
    """Angle [rad] of the rotation taking R_a to R_b (0..pi)."""
    R_rel = np.asarray(R_a, dtype=float)[:3, :3].T @ np.asarray(R_b, dtype=float)[:3, :3]
    cos_angle = np.clip((np.trace(R_rel) - 1.0) / 2.0, -1.0, 1.0)
    return float(np.arccos(cos_angle))


def as_pose(T: ArrayLike, what: str = "pose") -> Mat4:
    """`T` as a 4x4 rigid transform (finite, orthonormal rotation, last row 0 0 0 1): the
    one check of a pose, everywhere one is given; InputError naming `what` otherwise."""
    try:
        T = np.asarray(T, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a 4x4 matrix of numbers") from None
    if T.shape != (4, 4):
        raise InputError(f"{what} must be a 4x4 matrix, got shape {T.shape}")
    if not np.all(np.isfinite(T)):
        raise InputError(f"{what} contains NaN or infinite values")
    if not np.allclose(T[3], [0.0, 0.0, 0.0, 1.0], atol=1e-9):
        raise InputError(f"{what} last row must be [0, 0, 0, 1], got {T[3].tolist()}")
    R = T[:3, :3]
    if not np.allclose(R.T @ R, np.eye(3), atol=1e-6) or np.linalg.det(R) < 0:
        raise InputError(f"{what} rotation part is not a proper rotation matrix")
    return T
