"""A depth camera that renders the simulated world: the robot's display meshes at the
measured joint positions, the object at its true pose and the table, on the CPU
rasteriser (graspframe/pictures/rasteriser.py), one depth sample per pixel; then the sensor noise of
graspframe/perception/depth_noise.py. The hand and the arm occlude what lies behind them
as they would for a real sensor."""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from graspframe.hal.depth_camera import CameraMount, DepthCamera, DepthImage
from graspframe.hal.descriptions import joints_by_name
from graspframe.hal.drivers import World, WorldConfig
from graspframe.perception.depth_noise import DepthNoise

TABLE_HALF_SIZE = 1.5  # [m] of table drawn around the object


class SimulatedDepthCamera(DepthCamera):
    name: ClassVar[str] = "simulated"
    model: ClassVar[str] = "structured light, Kinect class (rendered on the CPU)"

    def __init__(
        self, config: WorldConfig, mount: CameraMount, seed: int, noise_scale: float = 1.0
    ) -> None:
        if config.robot is None:
            raise ValueError("the simulated depth camera needs a mounted robot in the world")
        if config.object is None:
            raise ValueError("the simulated depth camera needs an object in the world")
        # The meshes and the renderer (trimesh, OpenGL) load with the first camera built.
        from graspframe.pictures.render3d import Placed
        from graspframe.pictures.robot_scene import RobotFigure, object_soup, table_soup

        self._placed = Placed
        self.config = config
        self.mount = mount
        self.noise = DepthNoise(noise_scale)
        self.rng = np.random.default_rng(seed)
        hand = config.hand
        self.figure = RobotFigure(config.robot.model, hand.finger_of_link(), {})
        self.arm_joint_names = config.robot.arm.joint_names
        self.object = object_soup(config.object)
        p_object = config.T_world_object[:3, 3]
        table = table_soup(p_object[:2], TABLE_HALF_SIZE, config.table_height)
        self.table = Placed(table, np.eye(4))  # the table soup is in the world frame

    def T_world_camera(self, q_by_joint: dict[str, float]) -> NDArray[np.float64]:
        mount = self.mount
        if mount.flange_frame is None:
            assert mount.T_world_camera is not None
            return mount.T_world_camera
        assert mount.T_flange_camera is not None
        T_world_flange = self.config.T_world_arm_base @ self.figure.T_root_frame(mount.flange_frame)
        return T_world_flange @ mount.T_flange_camera

    def capture(self, world: World) -> DepthImage:
        assert world.arm is not None and world.object is not None
        q = joints_by_name(
            self.arm_joint_names, world.arm.joint_positions(), world.hand.joint_positions()
        )
        q = self.config.hand.with_model_followers(q)
        self.figure.place(q)
        placed = [
            *self.figure.placed_links(self.config.T_world_arm_base).values(),
            self._placed(self.object, world.object.T_world_object()),
            self.table,
        ]
        T_world_camera = self.T_world_camera(q)
        ideal = ideal_depth(placed, self.mount.intrinsics, T_world_camera)
        c = self.mount.intrinsics
        measured = self.noise.apply(ideal, c.fx, c.fy, self.rng)
        return DepthImage(measured, c, T_world_camera)


def ideal_depth(placed, intrinsics, T_world_camera) -> NDArray[np.float32]:
    """The noiseless depth image [m] (+inf: nothing) of the placed soups."""
    from graspframe.common.transforms import inv_T
    from graspframe.pictures.render3d import renderer

    T_camera_world = inv_T(T_world_camera)
    corners = []
    for item in placed:
        T = T_camera_world @ item.T_world_soup
        corners.append(item.soup.positions @ T[:3, :3].T.astype(np.float32) + T[:3, 3])
    positions = np.concatenate(corners).astype(np.float32)
    return renderer().depth(intrinsics, positions)
