"""Choosing a grasp plan the robot can carry out without touching the table or the object.

For each variant of the grasp (graspframe/strategy/planner.py: `Variant`), in order, the
segments the executor will drive are built by the one builder the executor drives them
from (segments.py, through executor.planned_path): the jerk-limited transfer from the
arm's home to the via pose (ruckig, sampled every control period), then the straight
palm lines (descent, approach, back-off, lift), each at the waypoints the controller
tracks, one per control cycle, with the tracking IK the controller uses
(arm_motion.track_waypoint). Every configuration is checked with Pinocchio's collision
tools against the table and the object where the robot believes it is:

- transfer and descent to the pre-approach pose: no robot link may touch either;
- approach and back-off: no arm link may touch either, no hand link the table (the hand
  is meant to reach the object);
- lift: no arm link may touch the table (the object rises with the hand).

The hand is in its open preshape along the whole path. The volar strategy's corrections
(a retreat and an approach to a corrected goal, decided by a contact) cannot be checked
before the contact happens; they are lines of the same kind along the approach. The
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

from collections.abc import Iterator, Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from graspframe.errors import MotionError
from graspframe.floating_base import mount_floating
from graspframe.grasps import HumanGrasp
from graspframe.hal.descriptions import ArmDescription, HandDescription, joints_by_name
from graspframe.hal.objects import ObjectDescription
from graspframe.motion.arm_motion import CONTROL_PERIOD, track_waypoint
from graspframe.motion.collision import RobotCollisionChecker, object_obstacle, table_obstacle
from graspframe.motion.ik import IkSolver
from graspframe.motion.trajectory import JointLimits, plan_joint_trajectory
from graspframe.mounting import MountedRobot, mount
from graspframe.robot_model import summarize_urdf
from graspframe.strategy.executor import ExecutorParams, planned_path
from graspframe.strategy.held_test import HeldTest
from graspframe.strategy.planner import (
    GraspPlan,
    PlannerParams,
    PlanningError,
    Variant,
    plan_grasp,
)
from graspframe.strategy.segments import PalmLine
from graspframe.transforms import inv_T

YAWS_DEG = (0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0, 120.0, -120.0, 150.0, -150.0, 180.0)
RAISES = (0.0, 0.015, 0.03)  # [m] up an upright object's axis, side grasps only
HIGHER_VIA_RISE = 0.25  # [m]


@dataclass(frozen=True)
class CheckedPlan:
    """A plan whose path was checked: the plan, the robot it was checked on, where that
    robot's base stands, and one line per variant refused before it."""

    plan: GraspPlan
    robot: MountedRobot
    T_world_base: NDArray[np.float64]
    refused: tuple[str, ...] = field(default_factory=tuple)


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


def _tracked(
    ik: IkSolver, q_start: NDArray[np.float64], T_base_world: NDArray[np.float64], line: PalmLine
) -> list[NDArray[np.float64]]:
    """Arm configurations at a palm line's waypoints, tracked from q_start as the
    controller tracks them."""
    q = np.asarray(q_start, dtype=float)
    path = []
    for T_world_palm in line.waypoints(CONTROL_PERIOD):
        q = track_waypoint(ik, q, T_base_world @ T_world_palm)
        path.append(q)
    return path


def path_problem(
    plan: GraspPlan,
    robot: MountedRobot,
    T_world_base: NDArray[np.float64],
    hand: HandDescription,
    obj: ObjectDescription,
    table_height: float,
    ik: IkSolver | None = None,
    params: ExecutorParams | None = None,
    held: HeldTest | None = None,
) -> str | None:
    """None when the robot can drive the plan's segments (with the executor's `params`
    and the held test's lift, `held`) without touching the table or the object (see the
    module docstring), else the reason in words."""
    arm = robot.arm
    q_hand = dict(hand.preshape(plan.preshape).open_q)
    ik = ik or IkSolver(robot)
    tracking = IkSolver(robot, restarts=0)
    T_base_world = inv_T(T_world_base)
    path = planned_path(plan, params or ExecutorParams(), held or HeldTest())
    q_home = np.asarray(arm.home_q, dtype=float)
    lines: dict[str, list[NDArray[np.float64]]] = {}
    try:
        q_via = ik.solve(T_base_world @ path.T_world_palm_via, q_seed=q_home, q_hand=q_hand).q_arm
        limits = JointLimits.from_arm(arm)
        transfer = plan_joint_trajectory(q_home, q_via, limits, CONTROL_PERIOD).q
        q = q_via
        for segment in path.lines:
            lines[segment.name] = _tracked(tracking, q, T_base_world, segment)
            q = lines[segment.name][-1] if lines[segment.name] else q
    except MotionError as exc:
        return f"unreachable: {exc}"

    checker = RobotCollisionChecker(
        robot.model,
        T_world_base,
        [
            table_obstacle(table_height, plan.T_world_object_est[:2, 3]),
            object_obstacle(obj, plan.T_world_object_est),
        ],
    )
    full_hand_q = hand.with_model_followers(q_hand)
    hand_links = {link for links in hand.real_fingers.values() for link in links}
    arm_links = summarize_urdf(robot.model).links - hand_links

    def configurations(path: Sequence[NDArray[np.float64]]) -> list[dict[str, float]]:
        return [joints_by_name(arm.joint_names, q, full_hand_q) for q in path]

    checks: list[
        tuple[str, Sequence[NDArray[np.float64]], AbstractSet[str] | None, tuple | None]
    ] = [
        ("the transfer from home", list(transfer), None, None),
        ("the descent to the pre-approach pose", lines.get("descent", []), None, None),
        ("the approach (arm links)", lines["approach"], arm_links, None),
        ("the approach (hand on the table)", lines["approach"], hand_links, ("table",)),
        ("the back-off (arm links)", lines.get("back-off", []), arm_links, None),
        ("the back-off (hand on the table)", lines.get("back-off", []), hand_links, ("table",)),
        ("the lift (arm links on the table)", lines.get("lift", []), arm_links, ("table",)),
    ]
    for label, configs, links, obstacles in checks:
        hit = checker.first_collision_on_path(configurations(configs), links, obstacles)
        if hit is not None:
            return f"{label}: {hit[1].describe()}"
    return None


def choose_plan(
    grasp: HumanGrasp,
    T_object_human_palm: NDArray[np.float64],
    T_world_object_est: NDArray[np.float64],
    hand: HandDescription,
    arm: ArmDescription,
    obj: ObjectDescription,
    table_height: float,
    T_world_base: NDArray[np.float64],
    params: PlannerParams | None = None,
    executor_params: ExecutorParams | None = None,
    held: HeldTest | None = None,
) -> CheckedPlan:
    """The first variant of the grasp whose path (driven with `executor_params`, lifted
    by `held`) is collision-free on the arm standing at T_world_base, the hand straight
    on the flange, else through each of its mountings in turn; PlanningError listing
    every variant's reason when none is."""
    refused: list[str] = []
    first = plan_grasp(grasp, T_object_human_palm, T_world_object_est, hand, obj, table_height)
    for mounting in (None, *hand.mountings):
        robot = mount(arm, hand, mounting=mounting)
        ik = IkSolver(robot)
        for variant in variants(obj, first.approach == "side"):
            variant = replace(variant, mounting=mounting)
            plan = plan_grasp(
                grasp,
                T_object_human_palm,
                T_world_object_est,
                hand,
                obj,
                table_height,
                params,
                variant,
            )
            problem = path_problem(
                plan, robot, T_world_base, hand, obj, table_height, ik, executor_params, held
            )
            if problem is None:
                T_world_base = np.asarray(T_world_base, dtype=float)
                return CheckedPlan(plan, robot, T_world_base, tuple(refused))
            refused.append(f"{_describe(variant)}: {problem}")
    raise PlanningError(
        f"no collision-free path for the {hand.name} {grasp.value} grasp on {arm.name} "
        f"({len(refused)} variant{'s' if len(refused) != 1 else ''} tried; first: {refused[0]})"
    )


def floating_plan(
    grasp: HumanGrasp,
    T_object_human_palm: NDArray[np.float64],
    T_world_object_est: NDArray[np.float64],
    hand: HandDescription,
    obj: ObjectDescription,
    table_height: float,
    params: PlannerParams | None = None,
    executor_params: ExecutorParams | None = None,
    held: HeldTest | None = None,
) -> CheckedPlan:
    """The plan for the hand alone on the floating base, whose home is the via pose (no
    transfer); its segments are checked like an arm's."""
    plan = plan_grasp(
        grasp, T_object_human_palm, T_world_object_est, hand, obj, table_height, params
    )
    robot, T_world_base = mount_floating(hand, plan.T_world_palm_via)
    problem = path_problem(
        plan, robot, T_world_base, hand, obj, table_height, None, executor_params, held
    )
    if problem is not None:
        raise PlanningError(f"no collision-free path for the free {hand.name} hand: {problem}")
    return CheckedPlan(plan, robot, T_world_base)


def _describe(variant: Variant) -> str:
    parts = [f"yaw {variant.yaw_deg:+.0f} deg"]
    if variant.raise_along_axis:
        parts.append(f"{1000 * variant.raise_along_axis:.0f} mm higher")
    if variant.via_rise is not None:
        parts.append(f"via {1000 * variant.via_rise:.0f} mm up")
    if variant.mounting is not None:
        parts.append(f"{variant.mounting} mounting")
    return ", ".join(parts)
