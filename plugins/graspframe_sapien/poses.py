"""SAPIEN poses (position + quat_wxyz) <-> 4x4 `T_a_b` matrices."""

from __future__ import annotations

import numpy as np
import sapien
from numpy.typing import NDArray

from graspframe.common.transforms import R_from_quat_wxyz, make_T, quat_wxyz_from_R


def to_T(pose: sapien.Pose) -> NDArray[np.float64]:
    return make_T(R_from_quat_wxyz(pose.q), pose.p)


def to_pose(T: NDArray[np.float64]) -> sapien.Pose:
    T = np.asarray(T, dtype=float)
    return sapien.Pose(T[:3, 3], quat_wxyz_from_R(T[:3, :3]))
