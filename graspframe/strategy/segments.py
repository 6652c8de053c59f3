"""The palm's path for a plan: the motion segments the method's strategy drives, built in
one place for the executor that drives them and the collision check that checks them.

- transfer: a jerk-limited joint move from the arm's home to the via pose;
- descent: a straight palm line from the via to the pre-approach pose;
- approach: a straight line from the pre-approach pose to the goal (a volar approach
  may go on past the goal by the overshoot, looking for its first contact: that part
  is a search into the object and is not checked);
- back-off: back along the approach by the plan's volar gap (volar plans that back off);
- lift: straight up by the held test's lift height.

A straight line is driven one waypoint per control cycle (`PalmLine.waypoints`: the
points ArmMotion.move_palm_linear tracks), and checked at those same waypoints. The
volar strategy's corrections (a retreat along the approach, then an approach to a
corrected goal) are the same kind of line, built when the contact that asks for them
happens (`approach_line`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from graspframe.strategy.planner import GraspPlan

MIN_DESCENT = 1e-6  # [m] a shorter descent from the via to the pre-approach pose is skipped
UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class PalmLine:
    """A straight palm move: from T_world_palm_start along the world direction
    `direction` (any length: it is made unit where it is used, as ArmMotion does) by
    `distance` [m] at `speed` [m/s], the palm's orientation kept."""

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


def line(
    name: str, T_world_palm_start: NDArray[np.float64], offset_world: ArrayLike, speed: float
) -> PalmLine:
    """The line from T_world_palm_start by the world vector `offset_world` [m]."""
    offset = np.asarray(offset_world, dtype=float)
    distance = float(np.linalg.norm(offset))
    return PalmLine(name, np.asarray(T_world_palm_start, dtype=float), offset, distance, speed)


@dataclass(frozen=True)
class PalmPath:
    """The segments of a plan, in the order they are driven (see the module docstring);
    descent and back_off are None when the plan has none."""

    T_world_palm_via: NDArray[np.float64]
    descent: PalmLine | None
    approach: PalmLine
    back_off: PalmLine | None
    lift: PalmLine | None

    @property
    def lines(self) -> list[PalmLine]:
        return [s for s in (self.descent, self.approach, self.back_off, self.lift) if s]


def approach_line(
    plan: GraspPlan, T_world_palm_goal: NDArray[np.float64], distance: float, speed: float
) -> PalmLine:
    """The approach to a goal along the plan's approach direction, starting `distance`
    [m] before it."""
    a = np.asarray(plan.a_world, dtype=float)
    start = np.asarray(T_world_palm_goal, dtype=float).copy()
    start[:3, 3] -= distance * (a / np.linalg.norm(a))
    return PalmLine("approach", start, a, float(distance), speed)


def palm_path(
    plan: GraspPlan,
    descent_speed: float,
    approach_speed: float,
    back_off_speed: float,
    lift_height: float | None = None,
    lift_speed: float | None = None,
) -> PalmPath:
    """The planned segments of `plan` (approach_speed: the speed of this plan's approach,
    guarded for a volar one; no lift segment without lift_height and lift_speed)."""
    descent_offset = plan.T_world_palm_pre[:3, 3] - plan.T_world_palm_via[:3, 3]
    descent = None
    if np.linalg.norm(descent_offset) > MIN_DESCENT:
        descent = line("descent", plan.T_world_palm_via, descent_offset, descent_speed)
    approach = approach_line(
        plan, plan.T_world_palm_goal, plan.pre_approach_distance, approach_speed
    )
    T_world_palm_held = plan.T_world_palm_goal
    back_off = None
    if plan.volar and plan.volar_gap > 0:
        back_off = PalmLine(
            "back-off", plan.T_world_palm_goal, -approach.direction, plan.volar_gap, back_off_speed
        )
        T_world_palm_held = back_off.T_world_palm_end
    lift = None
    if lift_height is not None and lift_speed is not None:
        lift = line("lift", T_world_palm_held, lift_height * UP, lift_speed)
    return PalmPath(plan.T_world_palm_via, descent, approach, back_off, lift)
