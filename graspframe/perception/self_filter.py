"""The robot removed from a depth image: the robot's own model rendered at its measured
joint positions from the camera's pose (what a robot's self filter does with its
encoders), and every measured pixel within SELF_MARGIN of the robot's surface dropped."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from graspframe.common.transforms import inv_T
from graspframe.hal.depth_camera import DepthImage
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.pictures.render3d import renderer
from graspframe.pictures.robot_scene import RobotFigure

# [m] a measured pixel this close to (or in front of) the robot's rendered surface is the
# robot: several times the sensor's noise at 1 m (perception/depth_noise.py).
SELF_MARGIN = 0.015


class RobotSelfFilter:
    """The robot of `model` (root at T_world_root) as a depth camera sees it."""

    def __init__(self, model: UrdfModel, T_world_root: NDArray[np.float64]) -> None:
        self.figure = RobotFigure(model, {}, {})
        self.T_world_root = T_world_root

    def robot_depth(self, image: DepthImage, q_by_joint: Mapping[str, float]) -> NDArray:
        """The robot's own depth image [m] (+inf: not the robot) for `image`'s camera."""
        self.figure.place(q_by_joint)
        T_camera_world = inv_T(image.T_world_camera)
        corners = []
        for link in self.figure.placed_links(self.T_world_root).values():
            T = T_camera_world @ link.T_world_soup
            corners.append(link.soup.positions @ T[:3, :3].T.astype(np.float32) + T[:3, 3])
        if not corners:
            return np.full(image.depth_m.shape, np.inf, dtype=np.float32)
        return renderer().depth(image.intrinsics, np.concatenate(corners).astype(np.float32))

    def without_robot(self, image: DepthImage, q_by_joint: Mapping[str, float]) -> DepthImage:
        """`image` with the robot's pixels set to NaN (no return)."""
        robot = self.robot_depth(image, q_by_joint)
        depth = image.depth_m.copy()
        with np.errstate(invalid="ignore"):
            depth[depth >= robot - SELF_MARGIN] = np.nan
        return DepthImage(depth, image.intrinsics, image.T_world_camera)
