"""Checking the motion segments of a grasp for collisions (a plan's path, before anything
moves: strategy/arm_path.py).

A segment is checked at the configurations the controller passes through: a jerk-limited
joint move sampled every control period (ruckig, from rest to rest), a straight palm
line at its waypoints (`PalmLine.waypoints`), tracked from the arm's joints as the
controller tracks them (arm_motion.track_waypoint). The hand is in its open preshape,
the table and the object where the robot believes it are the obstacles, and which links
may touch what depends on the kind of segment (`Rule`):

- a joint move (the transfer): no robot link may touch either;
- the descent to the pre-approach pose: the same;
- an approach, a back-off: no arm link may touch either, no hand link the table (the
  hand is meant to reach the object);
- the lift: no arm link may touch the table (the object rises with the hand).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass
from enum import Enum

import numpy as np
from numpy.typing import NDArray

from graspframe.common.transforms import inv_T
from graspframe.hal.descriptions import joints_by_name
from graspframe.motion.arm_motion import CONTROL_PERIOD, track_waypoint
from graspframe.motion.collision import RobotCollisionChecker, object_obstacle, table_obstacle
from graspframe.motion.ik import IkSolver
from graspframe.motion.palm_line import PalmLine
from graspframe.motion.trajectory import JointLimits, plan_joint_trajectory
from graspframe.robot_models.model import summarize_urdf
from graspframe.robot_models.mounting import MountedRobot
from graspframe.strategy.planner import GraspPlan, PlanningTarget


class Rule(Enum):
    """Which links of the robot may not touch which obstacles on a kind of segment (see
    the module docstring)."""

    CLEAR = "clear"  # joint moves, the descent
    REACHING = "reaching"  # approaches, back-offs
    LIFTING = "lifting"  # the lift


@dataclass(frozen=True)
class _Check:
    label: str  # appended to the segment's name in a refusal
    links: str  # "all", "arm" or "hand"
    obstacles: tuple[str, ...] | None  # None: the table and the object


CHECKS = {
    Rule.CLEAR: (_Check("", "all", None),),
    Rule.REACHING: (
        _Check(" (arm links)", "arm", None),
        _Check(" (hand on the table)", "hand", ("table",)),
    ),
    Rule.LIFTING: (_Check(" (arm links on the table)", "arm", ("table",)),),
}


class SegmentChecker:
    """Checks segments of `plan` for `target` on `robot` standing at T_world_base, among
    the target's table and its object where the plan believes it."""

    def __init__(
        self,
        plan: GraspPlan,
        target: PlanningTarget,
        robot: MountedRobot,
        T_world_base: NDArray[np.float64],
    ) -> None:
        hand, obj, table_height = target.hand, target.obj, target.table_height
        self.arm = robot.arm
        self.T_base_world = inv_T(np.asarray(T_world_base, dtype=float))
        self.tracking = IkSolver(robot, restarts=0)
        self.limits = JointLimits.from_arm(robot.arm)
        self.q_hand = dict(hand.preshape(plan.preshape).open_q)
        self.full_hand_q = hand.with_model_followers(self.q_hand)
        self.robot, self.T_world_base = robot, np.asarray(T_world_base, dtype=float)
        self.obstacles = [
            table_obstacle(table_height, plan.T_world_object_est[:2, 3]),
            object_obstacle(obj, plan.T_world_object_est),
        ]
        hand_links = {link for links in hand.real_fingers.values() for link in links}
        self.links: dict[str, AbstractSet[str] | None] = {
            "all": None,
            "arm": summarize_urdf(robot.model).links - hand_links,
            "hand": hand_links,
        }

    @functools.cached_property
    def checker(self) -> RobotCollisionChecker:
        """Built on the first check (a plan unreachable on the way needs none)."""
        return RobotCollisionChecker(self.robot.model, self.T_world_base, self.obstacles)

    def joint_move(
        self, q_from: NDArray[np.float64], q_to: NDArray[np.float64]
    ) -> list[NDArray[np.float64]]:
        """The arm's joints [rad] every control period of a jerk-limited move from rest
        at q_from to rest at q_to."""
        return list(plan_joint_trajectory(q_from, q_to, self.limits, CONTROL_PERIOD).q)

    def tracked(self, q_start: NDArray[np.float64], line: PalmLine) -> list[NDArray[np.float64]]:
        """The arm's joints [rad] at a palm line's waypoints, tracked from q_start as the
        controller tracks them; MotionError when the line cannot be followed."""
        q = np.asarray(q_start, dtype=float)
        path = []
        for T_world_palm in line.waypoints(CONTROL_PERIOD):
            q = track_waypoint(self.tracking, q, self.T_base_world @ T_world_palm)
            path.append(q)
        return path

    def problem(self, name: str, path: Sequence[NDArray[np.float64]], rule: Rule) -> str | None:
        """None when the configurations `path` of the segment `name` are clear under
        `rule`, else the first contact in words."""
        configurations = [joints_by_name(self.arm.joint_names, q, self.full_hand_q) for q in path]
        for check in CHECKS[rule]:
            hit = self.checker.first_collision_on_path(
                configurations, self.links[check.links], check.obstacles
            )
            if hit is not None:
                return f"{name}{check.label}: {hit[1].describe()}"
        return None
