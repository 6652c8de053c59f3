"""A straight palm move (`PalmLine`) and the waypoints that drive it: the one place they
are computed, for the arm's motion that follows a line (arm_motion.ArmMotion.follow)
and the path check that checks it (strategy/arm_path.py)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class PalmLine:
    """A straight palm move: from T_world_palm_start along the world direction
    `direction` (any length: it is made unit where it is used) by `distance` [m] at
    `speed` [m/s], the palm's orientation kept."""

    name: str
    T_world_palm_start: NDArray[np.float64]
    direction: NDArray[np.float64]
    distance: float
    speed: float

    @property
    def T_world_palm_end(self) -> NDArray[np.float64]:
        return self.T_world_palm_at(self.distance)

    @property
    def unit_direction(self) -> NDArray[np.float64]:
        return self.direction / np.linalg.norm(self.direction)

    def T_world_palm_at(self, s: float) -> NDArray[np.float64]:
        """The palm pose `s` [m] along the line."""
        T = self.T_world_palm_start.copy()
        T[:3, 3] += s * self.unit_direction
        return T

    def waypoints(self, control_period: float) -> list[NDArray[np.float64]]:
        """The palm poses the controller tracks, one per control cycle [s]: every
        speed * control_period along the line, the last at its end."""
        n = math.ceil(self.distance / self.speed / control_period)
        return [
            self.T_world_palm_at(min(k * control_period * self.speed, self.distance))
            for k in range(1, n + 1)
        ]

    def started_at(self, T_world_palm_start: NDArray[np.float64]) -> PalmLine:
        """The same move (direction, distance, speed) from another start pose."""
        return replace(self, T_world_palm_start=np.asarray(T_world_palm_start, dtype=float))

    def extended(self, further: float) -> PalmLine:
        """The same line going on `further` [m] past its end."""
        return replace(self, distance=self.distance + further)
