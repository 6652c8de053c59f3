"""The palm's path for a plan: the motion segments the method's strategy drives, built in
one place for the executor that drives them and the collision check that checks them
(arm_path.py).

- transfer: a jerk-limited joint move from the arm's home to the via pose;
- descent: a straight palm line from the via to the pre-approach pose;
- approach: a straight line from the pre-approach pose to the goal (a volar approach
  may go on past the goal by the overshoot, looking for its first contact: that part
  is a search into the object and is not checked);
- back-off: back along the approach by the plan's volar gap (volar plans that back off);
- lift: straight up by the held test's lift height (`lift_line`, which the held test
  drives).

A straight line (`PalmLine`, motion/palm_line.py) is driven one waypoint per control
cycle (`PalmLine.waypoints`, followed by `ArmMotion.follow` from the arm's commanded
palm pose), and checked at those same waypoints. The corrections decided while the
strategy runs are built here too, when the contact or the look that asks for them
happens: the volar loop's retreat (`retreat_line`) and its approach to a corrected goal
(`approach_line`, after a joint move to its start), the servo strategy's shifted path
(`PalmPath.shifted`, `approach_line`) and its sideways move at the standoff
(`sideways_line`). Those are not collision-checked (arm_path.py says why).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from graspframe.motion.palm_line import PalmLine

if TYPE_CHECKING:  # plans are only read here: the held test's lift needs no planner
    from graspframe.strategy.planner import GraspPlan

MIN_DESCENT = 1e-6  # [m] a shorter descent from the via to the pre-approach pose is skipped
UP = np.array([0.0, 0.0, 1.0])


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

    def shifted(self, shift_world: NDArray[np.float64]) -> PalmPath:
        """The whole path moved by `shift_world` [m] (the servo strategy's corrections)."""

        def moved(segment: PalmLine | None) -> PalmLine | None:
            if segment is None:
                return None
            return segment.started_at(moved_pose(segment.T_world_palm_start, shift_world))

        approach = moved(self.approach)
        assert approach is not None
        return PalmPath(
            moved_pose(self.T_world_palm_via, shift_world),
            moved(self.descent),
            approach,
            moved(self.back_off),
            moved(self.lift),
        )


def moved_pose(T: NDArray[np.float64], shift_world: NDArray[np.float64]) -> NDArray[np.float64]:
    """The pose T translated by `shift_world` [m] (world frame)."""
    T_moved = T.copy()
    T_moved[:3, 3] += shift_world
    return T_moved


def approach_line(
    plan: GraspPlan, T_world_palm_goal: NDArray[np.float64], distance: float, speed: float
) -> PalmLine:
    """The approach to a goal along the plan's approach direction, starting `distance`
    [m] before it."""
    a = np.asarray(plan.a_world, dtype=float)
    start = np.asarray(T_world_palm_goal, dtype=float).copy()
    start[:3, 3] -= distance * (a / np.linalg.norm(a))
    return PalmLine("approach", start, a, float(distance), speed)


def retreat_line(
    plan: GraspPlan, T_world_palm_from: NDArray[np.float64], distance: float, speed: float
) -> PalmLine:
    """Back along the plan's approach direction by `distance` [m] from T_world_palm_from:
    the volar loop's retreat from a contact that asks for a corrected goal."""
    a = np.asarray(plan.a_world, dtype=float)
    return PalmLine("retreat", np.asarray(T_world_palm_from, dtype=float), -a, distance, speed)


def lift_line(T_world_palm_from: NDArray[np.float64], height: float, speed: float) -> PalmLine:
    """The held test's lift: straight up (world +z) by `height` [m] from
    T_world_palm_from."""
    return PalmLine("lift", np.asarray(T_world_palm_from, dtype=float), UP, height, speed)


def sideways_line(
    T_world_palm_from: NDArray[np.float64], shift_world: NDArray[np.float64], speed: float
) -> PalmLine:
    """A short move by the world vector `shift_world` [m] from T_world_palm_from: the
    servo strategy's correction at the standoff."""
    distance = float(np.linalg.norm(shift_world))
    start = np.asarray(T_world_palm_from, dtype=float)
    return PalmLine("standoff shift", start, shift_world / distance, distance, speed)


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
        lift = lift_line(T_world_palm_held, lift_height, lift_speed)
    return PalmPath(plan.T_world_palm_via, descent, approach, back_off, lift)
