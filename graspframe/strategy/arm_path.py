"""Choosing a grasp plan the robot can carry out without touching the table or the object.

For each variant of the grasp (graspframe/strategy/planner.py: `Variant`), in order, the
segments the executor will drive are built by the one builder the executor drives them
from (segments.py, through method.planned_path): the jerk-limited transfer from the
arm's home to the via pose, then the straight palm lines (descent, approach, back-off,
lift). Each is checked at the configurations the controller passes through, against the
table and the object where the robot believes it is (path_check.py: the transfer and
the descent may touch nothing; the approach and the back-off may touch the object with
the hand; the lift may not touch the table with the arm).

The volar strategy's corrections (a retreat and an approach to a corrected goal, decided
by a contact) and the servo strategy's shifted segments cannot be checked before the
contact or the look that asks for them; they are built by segments.py too, but not
checked while the strategy runs (checked with these rules, a correction of experiment B
that holds would be refused: a link 5.0 mm from the table against the 5 mm margin). The
first variant that passes wins; when none does, the plan is refused with the reason of
each variant tried.

The variants are first tried with the hand's root link bolted straight onto the flange,
then through each adapter the hand declares (`HandDescription.mountings`), in order. An
adapter changes where the arm's wrist is relative to the palm: a hand whose fingers
continue the flange axis (an anthropomorphic wrist) holding a short upright object with
its fingers tilted up puts the arm's wrist below the palm, into the table, in every
variant; an adapter on the back of the hand lifts the wrist above it. The adapter's
shapes are checked like the arm's links.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import MotionError
from graspframe.hal.descriptions import ArmDescription
from graspframe.hal.objects import ObjectDescription
from graspframe.motion.ik import IkSolver
from graspframe.robot_models.floating_base import mount_floating
from graspframe.robot_models.mounting import MountedRobot, check_mounts
from graspframe.strategy.held_check import HeldTest
from graspframe.strategy.method import ExecutorParams, planned_path
from graspframe.strategy.path_check import Rule, SegmentChecker
from graspframe.strategy.planner import (
    GraspPlan,
    PlannerParams,
    PlanningError,
    PlanningTarget,
    Variant,
    plan_grasp,
)

YAWS_DEG = (0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0, 120.0, -120.0, 150.0, -150.0, 180.0)
RAISES = (0.0, 0.015, 0.03)  # [m] up an upright object's axis, side grasps only
HIGHER_VIA_RISE = 0.25  # [m]
# The planned segments by PalmLine name (segments.py): their names in a refusal, and what
# they may touch (path_check.py).
SEGMENT_NAMES = {
    "descent": "the descent to the pre-approach pose",
    "approach": "the approach",
    "back-off": "the back-off",
    "lift": "the lift",
}
SEGMENT_RULES = {
    "descent": Rule.CLEAR,
    "approach": Rule.REACHING,
    "back-off": Rule.REACHING,
    "lift": Rule.LIFTING,
}


@dataclass(frozen=True)
class CheckedPlan:
    """A plan whose path was checked: the plan, the robot it was checked on, where that
    robot's base stands, one line per variant refused before it, and the executor's
    settings its segments were built with (the ones to drive it with)."""

    plan: GraspPlan
    robot: MountedRobot
    T_world_base: NDArray[np.float64]
    refused: tuple[str, ...] = field(default_factory=tuple)
    executor_params: ExecutorParams = field(default_factory=ExecutorParams)


def variants(obj: ObjectDescription, side: bool) -> Iterator[Variant]:
    """The alternatives tried in order: as planned, a higher via, then turned about the
    object's axis (symmetric objects), then held higher up the object (side grasps)."""
    yaws = YAWS_DEG if obj.symmetric_about_z else (0.0,)
    raises = RAISES if side else (0.0,)
    seen = set()
    for raise_along_axis in raises:
        if raise_along_axis > obj.half_height:
            continue
        for yaw in yaws:
            for via_rise in (None, HIGHER_VIA_RISE) if side else (None,):
                key = (raise_along_axis, yaw, via_rise)
                if key not in seen:
                    seen.add(key)
                    yield Variant(yaw_deg=yaw, raise_along_axis=raise_along_axis, via_rise=via_rise)


def path_problem(
    plan: GraspPlan,
    target: PlanningTarget,
    robot: MountedRobot,
    T_world_base: NDArray[np.float64],
    ik: IkSolver | None = None,
    params: ExecutorParams | None = None,
    held: HeldTest | None = None,
) -> str | None:
    """None when the robot can drive the plan's segments (with the executor's `params`
    and the held test's lift, `held`) without touching the table or the object (see the
    module docstring), else the reason in words."""
    check = SegmentChecker(plan, target, robot, T_world_base)
    ik = ik or IkSolver(robot)
    path = planned_path(plan, params or ExecutorParams(), held or HeldTest())
    q_home = np.asarray(robot.arm.home_q, dtype=float)
    T_base_palm_via = check.T_base_world @ path.T_world_palm_via
    segments: list[tuple[str, list[NDArray[np.float64]], Rule]] = []
    try:
        q_via = ik.solve(T_base_palm_via, q_seed=q_home, q_hand=check.q_hand).q_arm
        segments.append(("the transfer from home", check.joint_move(q_home, q_via), Rule.CLEAR))
        q = q_via
        for segment in path.lines:
            tracked = check.tracked(q, segment)
            segments.append((SEGMENT_NAMES[segment.name], tracked, SEGMENT_RULES[segment.name]))
            q = tracked[-1] if tracked else q
    except MotionError as exc:
        return f"unreachable: {exc}"
    for name, configurations, rule in segments:
        problem = check.problem(name, configurations, rule)
        if problem is not None:
            return problem
    return None


def choose_plan(
    target: PlanningTarget,
    arm: ArmDescription,
    T_world_base: NDArray[np.float64],
    params: PlannerParams | None = None,
    executor_params: ExecutorParams | None = None,
    held: HeldTest | None = None,
    robots: Mapping[str | None, MountedRobot] | None = None,
) -> CheckedPlan:
    """The first variant of the grasp whose path (driven with `executor_params`, lifted
    by `held`) is collision-free on the arm standing at T_world_base, the hand straight
    on the flange, else through each of its mountings in turn; PlanningError listing
    every variant's reason when none is. robots: the hand already mounted, by mounting
    (None: straight on), as `check_mounts` gives them (the mounts that clear the arm);
    mounted here when not given."""
    executor_params = executor_params or ExecutorParams()
    refused: list[str] = []
    hand, obj = target.hand, target.obj
    first = plan_grasp(target)
    robots = robots or check_mounts(arm, hand)
    for mounting in (None, *hand.mountings):
        if mounting not in robots:
            refused.append(f"{_mounted(mounting)}: its links overlap the arm's (check-hand)")
            continue
        robot = robots[mounting]
        ik = IkSolver(robot)
        for variant in variants(obj, first.approach == "side"):
            variant = replace(variant, mounting=mounting)
            plan = plan_grasp(target, params, variant)
            problem = path_problem(plan, target, robot, T_world_base, ik, executor_params, held)
            if problem is None:
                T_world_base = np.asarray(T_world_base, dtype=float)
                return CheckedPlan(plan, robot, T_world_base, tuple(refused), executor_params)
            refused.append(f"{_describe(variant)}: {problem}")
    raise PlanningError(
        f"no collision-free path for the {hand.name} {target.grasp.value} grasp on {arm.name} "
        f"({len(refused)} variant{'s' if len(refused) != 1 else ''} tried; first: {refused[0]})"
    )


def floating_plan(
    target: PlanningTarget,
    params: PlannerParams | None = None,
    executor_params: ExecutorParams | None = None,
    held: HeldTest | None = None,
) -> CheckedPlan:
    """The plan for the hand alone on the floating base, whose home is the via pose (no
    transfer); its segments are checked like an arm's."""
    executor_params = executor_params or ExecutorParams()
    plan = plan_grasp(target, params)
    robot, T_world_base = mount_floating(target.hand, plan.T_world_palm_via)
    problem = path_problem(plan, target, robot, T_world_base, None, executor_params, held)
    if problem is not None:
        raise PlanningError(
            f"no collision-free path for the free {target.hand.name} hand: {problem}"
        )
    return CheckedPlan(plan, robot, T_world_base, executor_params=executor_params)


def _mounted(mounting: str | None) -> str:
    return "bolted straight on" if mounting is None else f"through the {mounting} mounting"


def _describe(variant: Variant) -> str:
    parts = [f"yaw {variant.yaw_deg:+.0f} deg"]
    if variant.raise_along_axis:
        parts.append(f"{1000 * variant.raise_along_axis:.0f} mm higher")
    if variant.via_rise is not None:
        parts.append(f"via {1000 * variant.via_rise:.0f} mm up")
    if variant.mounting is not None:
        parts.append(f"{variant.mounting} mounting")
    return ", ".join(parts)
