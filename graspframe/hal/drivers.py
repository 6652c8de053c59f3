"""How to move a robot: the backend and driver interfaces (the hardware abstraction layer).

A `Backend` builds a `World` (a table, an object, and a hand mounted on an arm or
floating freely) and hands out drivers. Core code (planner, executor, metric) speaks only
these interfaces, so the SAPIEN simulator and a hardware backend are interchangeable.
Core code never imports a simulator.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact, PalmSensorReading
from graspframe.common.errors import GraspframeError
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.hal.objects import ObjectDescription


@dataclass(frozen=True)
class WorldConfig:
    """Everything a backend needs to build a world.

    hand: the hand, mounted on the arm of `robot` or floating freely.
    robot: the hand fixed to an arm's flange (`MountedRobot`, built by
        `graspframe.robot_models.mounting.mount`): the arm, the pose of the hand on the flange, any
        adapter, and the combined model file a backend loads. The core mounts the hand;
        a backend only reads the result. None: a free-floating hand (placed with
        `HandDriver.set_free_pose`).
    T_world_arm_base: pose of the arm base in the world.
    T_world_object: true pose of the object's centroid frame in the world.
    table_height: [m] height of the table top (world z up).
    timestep: physics step [s].
    seed: seeds everything random in the world.
    """

    hand: HandDescription
    object: ObjectDescription | None
    robot: MountedRobot | None = None
    T_world_arm_base: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))
    T_world_object: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))
    table_height: float = 0.0
    timestep: float = 1.0 / 500.0
    seed: int = 0

    def __post_init__(self) -> None:
        if self.robot is not None and self.robot.hand.name != self.hand.name:
            raise GraspframeError(
                f"the world's hand {self.hand.name!r} is not the mounted robot's "
                f"hand {self.robot.hand.name!r}"
            )

    @property
    def arm(self) -> ArmDescription | None:
        """The arm the hand is mounted on (None: a free-floating hand)."""
        return None if self.robot is None else self.robot.arm


class ArmDriver(ABC):
    """Joint-level access to an arm."""

    @property
    @abstractmethod
    def joint_names(self) -> tuple[str, ...]: ...

    @abstractmethod
    def set_joint_targets(
        self,
        q: Sequence[float] | NDArray[np.float64],
        qd: Sequence[float] | NDArray[np.float64] | None = None,
    ) -> None:
        """Command joint positions [rad] (and optionally velocities [rad/s])."""

    @abstractmethod
    def joint_positions(self) -> NDArray[np.float64]:
        """Measured joint positions [rad], in `joint_names` order."""


class HandDriver(ABC):
    """Joint-level access to a hand, its contacts and its palm sensor."""

    @property
    @abstractmethod
    def joint_names(self) -> tuple[str, ...]: ...

    @abstractmethod
    def set_joint_targets(self, q_by_joint: Mapping[str, float]) -> None:
        """Command the named actuated joints [rad]; others keep their targets."""

    @abstractmethod
    def joint_positions(self) -> dict[str, float]:
        """Measured positions [rad] of the actuated joints."""

    def follower_positions(self) -> dict[str, float]:
        """Measured positions [rad] of the model's <mimic> followers (the joints its model
        couples to a leader: `Coupling.in_model`); none when the backend cannot tell."""
        return {}

    @abstractmethod
    def contacts(self) -> list[Contact]:
        """Current contacts between the hand and the object, in the world frame."""

    @abstractmethod
    def palm_sensor(self) -> PalmSensorReading:
        """The palm tactile sensor and first-contact detector: the touches since the
        previous reading (a touch shorter than one control cycle is not lost), or the
        current contacts when nothing touched in between. Reading it resets it."""

    @abstractmethod
    def T_world_palm(self) -> NDArray[np.float64]:
        """Measured pose of the palm frame in the world."""

    def set_free_pose(self, T_world_palm: NDArray[np.float64]) -> None:
        """Command the pose of a free-floating hand's palm (free-floating worlds only)."""
        raise NotImplementedError(f"{type(self).__name__} drives a hand mounted on an arm")


class ObjectProbe(ABC):
    """Reads the true state of the object (ground truth in simulation)."""

    @abstractmethod
    def T_world_object(self) -> NDArray[np.float64]: ...

    def apply_force(self, f_world: NDArray[np.float64] | None) -> None:
        """Push the object's centroid with a constant force [N] (world frame) on every
        following step, until called again (None: stop pushing). The disturbance test of
        a grasp uses it; a backend that cannot push the object (hardware) leaves this
        default, and that test is then reported as not run."""
        raise NotImplementedError(f"{type(self).__name__} cannot push the object")


class World(ABC):
    """A built world: drivers plus the clock. `step` advances by one physics step."""

    hand: HandDriver
    arm: ArmDriver | None
    object: ObjectProbe | None

    @property
    @abstractmethod
    def time(self) -> float:
        """Simulation (or wall) time since the world was built [s]."""

    @property
    @abstractmethod
    def timestep(self) -> float:
        """Duration of one `step` [s]."""

    @abstractmethod
    def step(self, n: int = 1) -> None: ...

    def close(self) -> None:  # noqa: B027 - optional hook, nothing to release by default
        """Release resources."""

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class Backend(ABC):
    """Builds worlds. Registered as a class; `name` is what users select."""

    name: ClassVar[str]
    summary: ClassVar[str] = ""

    @abstractmethod
    def create_world(self, config: WorldConfig) -> World: ...
