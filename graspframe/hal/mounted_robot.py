"""`MountedRobot`: a hand fixed to an arm's flange, as data (what `WorldConfig.robot`
carries to a backend). graspframe/robot_models/mounting.py builds it: the names, the
pose of the hand on the flange and the combined model."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.model_files.urdf_model import UrdfModel


@dataclass(frozen=True)
class MountedRobot:
    """A hand fixed to an arm's flange.

    arm: the arm as mounted (its names prefixed when they clashed with the hand's).
    model: the combined model (arm links, then hand links, one fixed mount joint).
    T_flange_hand: pose of the hand's root link in the flange frame.
    mounting: the name of the hand's `Mounting` used (None: no adapter).
    """

    arm: ArmDescription
    hand: HandDescription
    model: UrdfModel
    mount_joint: str
    T_flange_hand: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))
    mounting: str | None = None

    @property
    def name(self) -> str:
        return f"{self.arm.name}+{self.hand.name}"
