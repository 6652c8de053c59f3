"""A depth camera: what it sees of the world, as a depth image with its intrinsics and pose.

A `DepthCamera` is registered by a plugin as a class (registry kind "camera") and built
for one world with `DepthCamera(config, mount, seed)`: the simulated camera renders the
world's geometry (plugins/graspframe_depth_sim), a driver of a real RGB-D camera would
read the device and ignore the geometry. `capture(world)` returns a `DepthImage`.

Frames: the camera frame is OpenCV's (x right, y down, z forward along the optical
axis); `T_world_camera` places it in the world. Depth is the camera frame's z [m]; a
pixel without a return is NaN.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from graspframe.common.camera import Camera
from graspframe.common.moved_modules import moved_name
from graspframe.hal.drivers import World, WorldConfig


@dataclass(frozen=True)
class CameraMount:
    """Where a camera looks from: `T_world_camera` (a head camera, fixed in the world), or,
    with `flange_frame` set, `T_flange_camera` on that link of the robot (a wrist
    camera); `intrinsics`: pixels and focal lengths."""

    intrinsics: Camera
    T_world_camera: NDArray[np.float64] | None = None
    flange_frame: str | None = None
    T_flange_camera: NDArray[np.float64] | None = None


@dataclass(frozen=True)
class DepthImage:
    """One depth image: `depth_m` (H x W, camera-frame z [m], NaN: no return), the
    camera's intrinsics and its pose in the world when the image was taken."""

    depth_m: NDArray[np.float32]
    intrinsics: Camera
    T_world_camera: NDArray[np.float64]

    def points_camera(self) -> NDArray[np.float64]:
        """(n, 3) [m] the pixels with a return, back-projected into the camera frame."""
        rows, columns = np.nonzero(np.isfinite(self.depth_m))
        z = self.depth_m[rows, columns].astype(np.float64)
        c = self.intrinsics
        x = (columns + 0.5 - c.cx) / c.fx * z
        y = (rows + 0.5 - c.cy) / c.fy * z
        return np.stack([x, y, z], axis=1)

    def points_world(self) -> NDArray[np.float64]:
        """(n, 3) [m] the pixels with a return, in the world frame."""
        p_camera = self.points_camera()
        T = self.T_world_camera
        return p_camera @ T[:3, :3].T + T[:3, 3]


class DepthCamera(ABC):
    """A depth sensor in one world. `name`: its registered name; `model`: the sensor
    class it models or drives, in a few words (shown by `graspframe plugins`)."""

    name: ClassVar[str]
    model: ClassVar[str] = ""

    @abstractmethod
    def __init__(
        self, config: WorldConfig, mount: CameraMount, seed: int, noise_scale: float = 1.0
    ) -> None:
        """A camera for the world built from `config`, mounted as `mount`; `seed` seeds
        its noise (the same seed, world and poses give the same images); a simulated
        camera multiplies its noise by `noise_scale`, a real one ignores it."""

    @abstractmethod
    def capture(self, world: World) -> DepthImage:
        """One depth image of the world as it is now (robot, object and table; the
        hand and arm occlude what lies behind them)."""


def __getattr__(name: str) -> object:
    # `Intrinsics` was this module's pinhole camera: it is graspframe.common.camera.Camera.
    if name == "Intrinsics":
        return moved_name(__name__, name, "graspframe.common.camera", new_name="Camera")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
