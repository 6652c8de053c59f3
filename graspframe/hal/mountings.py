"""How a hand is held by an arm's flange other than bolted straight on: a `Mounting`
through an adapter, whose shapes (`AdapterShape`) the collision checks and the simulator
see as part of the arm. Pure data, as the descriptions that carry them
(graspframe/hal/descriptions.py: `HandDescription.mountings`)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from graspframe.common.errors import DescriptionError
from graspframe.common.transforms import as_pose
from graspframe.hal.objects import SHAPES


@dataclass(frozen=True)
class AdapterShape:
    """One collision shape of a mounting adapter, fixed to the hand's root link.

    shape: "box" (dimensions size_x, size_y, size_z), "cylinder" (radius, length, along
        its own z) or "sphere" (radius) [m], as for objects.
    T_root_shape: pose of the shape's centre in the hand's root-link frame.
    """

    shape: str
    dimensions: Mapping[str, float]
    T_root_shape: np.ndarray = field(default_factory=lambda: np.eye(4))

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise DescriptionError(
                f"adapter shape {self.shape!r} is unknown; shapes are {', '.join(SHAPES)}"
            )
        if set(self.dimensions) != set(SHAPES[self.shape]) or any(
            not (math.isfinite(v) and v > 0) for v in self.dimensions.values()
        ):
            raise DescriptionError(
                f"an adapter {self.shape} needs dimensions {', '.join(SHAPES[self.shape])} "
                f"> 0 [m], got {dict(self.dimensions)}"
            )
        object.__setattr__(self, "T_root_shape", as_pose(self.T_root_shape, "T_root_shape"))


@dataclass(frozen=True)
class Mounting:
    """A way of fixing a hand to an arm flange other than bolting its root link straight
    on: through an adapter.

    T_flange_hand: pose of the hand's root link in the arm's flange frame.
    adapter: the adapter's collision shapes (the collision checks and the simulator
        see them as part of the arm); mass: [kg] of the adapter.
    summary: one line saying what the adapter is and why.
    """

    T_flange_hand: np.ndarray
    adapter: tuple[AdapterShape, ...] = ()
    mass: float = 0.0
    summary: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "T_flange_hand", as_pose(self.T_flange_hand, "T_flange_hand"))
        object.__setattr__(self, "adapter", tuple(self.adapter))
        if not (math.isfinite(self.mass) and self.mass >= 0.0):
            raise DescriptionError(f"adapter mass must be finite and >= 0 kg, got {self.mass}")
