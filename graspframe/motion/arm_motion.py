"""Moving an arm through the driver interfaces: joint-space moves and straight palm lines.

One control cycle (CONTROL_PERIOD): the ruckig online generator yields the next joint
setpoint within the arm's velocity, acceleration and jerk limits, the arm driver gets it
as its target, and the world advances by the physics steps of one cycle. While the arm
holds still (the hand closing, the hold, the held test's waits) `idle` runs the world in
the same cycles, so observers hear of every cycle of a grasp. A straight palm move
(`follow` a `PalmLine`, motion/palm_line.py) solves IK (warm-started) for the waypoint
one cycle ahead and hands it to ruckig; when asked to, it checks the palm sensor after
every cycle and brakes at the first contact, so the stop begins within one control
cycle of the touch.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact
from graspframe.common.errors import GraspframeError, MotionError
from graspframe.common.transforms import inv_T
from graspframe.hal.drivers import World
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.motion.ik import IkSolver, describe_pose
from graspframe.motion.palm_line import PalmLine
from graspframe.motion.trajectory import JointLimits, OnlineTrajectory

CONTROL_PERIOD = 0.01  # [s] 100 Hz arm control
SETTLE_TIME_LIMIT = 3.0  # [s] longest wait for a braking or finishing move to come to rest
JOINT_MOVE_TIME_LIMIT = 30.0  # [s] longest a joint move may take before it counts as stuck
# Waypoint velocities handed to ruckig are scaled to at most this part of the joint
# velocity limits (near a wrist singularity a slow palm line needs fast wrist joints).
WAYPOINT_SPEED_FRACTION = 0.5
# Consecutive waypoints of a straight line may not move any joint more than this: a
# larger step means the IK switched solution branch, and the palm would leave the line.
MAX_WAYPOINT_JUMP = 0.3  # [rad]


def track_waypoint(
    tracking_ik: IkSolver, q_previous: NDArray[np.float64], T_base_palm: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The arm joints [rad] of the next waypoint of a straight palm line, continuous with
    the previous waypoint's (IK seeded with them, no restarts); MotionError when a joint
    would jump more than MAX_WAYPOINT_JUMP (the line passes a singularity or a limit).
    The executor drives lines with it and the path check checks them with it."""
    solution = tracking_ik.solve(T_base_palm, q_seed=q_previous)
    jump = float(np.abs(solution.q_arm - q_previous).max())
    if jump > MAX_WAYPOINT_JUMP:
        raise MotionError(
            f"the straight palm line cannot be followed near {describe_pose(T_base_palm)}: "
            f"the arm would jump {np.degrees(jump):.0f} deg between waypoints "
            "(a singularity or a joint limit on the way)"
        )
    return solution.q_arm


@dataclass(frozen=True)
class LinearMoveResult:
    """The outcome of a straight palm move.

    stopped_by_contact: the move braked at a contact before covering its distance.
    first_contact: the strongest contact when the touch was detected.
    palm_touched: the palm sensor was among the links touching at that moment.
    travel: [m] palm displacement along the move direction, start to rest.
    travel_after_contact: [m] palm displacement along the direction from the detection
        of the touch to rest (0 without a touch).
    duration: [s] simulated time of the move.
    """

    stopped_by_contact: bool
    first_contact: Contact | None
    palm_touched: bool
    T_world_palm_at_contact: NDArray[np.float64] | None
    T_world_palm_end: NDArray[np.float64]
    travel: float
    travel_after_contact: float
    duration: float
    cycles: int


class ArmMotion:
    """Drives the arm of one world: IK, the online trajectory and the control loop.

    on_cycle: called after every control cycle, moving (`cycle`) or holding still
    (`idle`), with this object (observers record the palm path and joint positions from
    it; the execution checks the joint limits).
    """

    def __init__(
        self,
        world: World,
        robot: MountedRobot,
        T_world_base: NDArray[np.float64],
        control_period: float = CONTROL_PERIOD,
        on_cycle: Callable[[ArmMotion], None] | None = None,
        ik: IkSolver | None = None,
    ) -> None:
        if world.arm is None:
            raise GraspframeError("ArmMotion needs a world with an arm")
        self.world = world
        self.arm = world.arm
        self.robot = robot
        self.T_world_base = np.asarray(T_world_base, dtype=float)
        self.ik = ik or IkSolver(robot)
        # Straight lines track from the previous solution only: a restart could land on
        # another IK branch.
        self.tracking_ik = IkSolver(robot, restarts=0)
        self.limits = JointLimits.from_arm(robot.arm)
        self.steps_per_cycle = max(1, round(control_period / world.timestep))
        self.control_period = self.steps_per_cycle * world.timestep
        self.trajectory = OnlineTrajectory(
            self.limits, self.control_period, world.arm.joint_positions()
        )
        self.on_cycle = on_cycle
        self.q_ik = world.arm.joint_positions()  # warm start for the next IK solve

    def cycle(self) -> None:
        """One control cycle: next setpoint to the arm, then the physics steps."""
        q, qd, _ = self.trajectory.step()
        self.arm.set_joint_targets(q, qd)
        self.world.step(self.steps_per_cycle)
        if self.on_cycle is not None:
            self.on_cycle(self)

    def idle(self, steps: int) -> None:
        """Run the world `steps` physics steps with the arm holding its target: whole
        control cycles, then the remainder, with on_cycle after each."""
        while steps > 0:
            n = min(steps, self.steps_per_cycle)
            self.world.step(n)
            steps -= n
            if self.on_cycle is not None:
                self.on_cycle(self)

    def solve_palm(self, T_world_palm: NDArray[np.float64]) -> NDArray[np.float64]:
        """Arm joints [rad] that put the palm at T_world_palm (warm-started IK)."""
        T_base_palm = inv_T(self.T_world_base) @ T_world_palm
        solution = self.ik.solve(T_base_palm, q_seed=self.q_ik)
        self.q_ik = solution.q_arm
        return solution.q_arm

    def _track(self, T_world_palm: NDArray[np.float64]) -> NDArray[np.float64]:
        """IK for the next waypoint of a line, continuous with the previous one."""
        self.q_ik = track_waypoint(
            self.tracking_ik, self.q_ik, inv_T(self.T_world_base) @ T_world_palm
        )
        return self.q_ik

    def _bounded_velocity(self, qd: NDArray[np.float64]) -> NDArray[np.float64]:
        ratio = float(np.max(np.abs(qd) / self.limits.max_velocity))
        if ratio > WAYPOINT_SPEED_FRACTION:
            qd = qd * (WAYPOINT_SPEED_FRACTION / ratio)
        return qd

    def _cycles_until_rest(self) -> int:
        cycles = 0
        limit = round(SETTLE_TIME_LIMIT / self.control_period)
        while not (self.trajectory.finished and self.trajectory.at_rest):
            if cycles >= limit:
                raise MotionError(f"the arm did not come to rest within {SETTLE_TIME_LIMIT} s")
            self.cycle()
            cycles += 1
        return cycles

    def move_to_joints(
        self, q_goal: NDArray[np.float64], time_limit: float = JOINT_MOVE_TIME_LIMIT
    ) -> float:
        """Jerk-limited joint move to q_goal [rad]; returns its duration [s]."""
        start = self.world.time
        self.trajectory.set_target(q_goal)
        limit = round(time_limit / self.control_period)
        for _ in range(limit):
            if self.trajectory.finished and self.trajectory.at_rest:
                break
            self.cycle()
        else:
            raise MotionError(f"the joint move did not finish within {time_limit} s")
        self.q_ik = np.asarray(q_goal, dtype=float)
        return self.world.time - start

    def move_palm_to(self, T_world_palm: NDArray[np.float64]) -> float:
        """Joint move to the IK solution for a palm pose; returns its duration [s]."""
        return self.move_to_joints(self.solve_palm(T_world_palm))

    def T_world_palm_commanded(self) -> NDArray[np.float64]:
        """The palm pose of the arm's last commanded joints (its IK solution, not the
        measured pose): where the next straight line starts."""
        return self.T_world_base @ self.ik.forward_palm(self.q_ik)

    def move_palm_linear(
        self,
        direction_world: NDArray[np.float64],
        distance: float,
        speed: float,
        stop_on_contact: bool = True,
        each_cycle: Callable[[], None] | None = None,
    ) -> LinearMoveResult:
        """`follow` the line from the commanded palm pose along `direction_world` by
        `distance` [m] at `speed` [m/s]."""
        direction = np.asarray(direction_world, dtype=float)
        line = PalmLine("line", self.T_world_palm_commanded(), direction, distance, speed)
        return self.follow(line, stop_on_contact, each_cycle)

    def follow(
        self,
        line: PalmLine,
        stop_on_contact: bool = True,
        each_cycle: Callable[[], None] | None = None,
    ) -> LinearMoveResult:
        """Move the palm along a straight line, orientation kept: the line's direction,
        distance [m] and speed [m/s] from the commanded palm pose (the IK solution of the
        last move, so its residual does not become a jump), one waypoint per control
        cycle (`PalmLine.waypoints`).

        With stop_on_contact, the palm sensor is read after every control cycle and the
        arm brakes (within its limits) at the first contact. each_cycle: called after
        every control cycle of the move (e.g. to sample the object).
        """
        norm = np.linalg.norm(line.direction)
        if not (norm > 0 and line.distance >= 0 and line.speed > 0):
            raise GraspframeError(
                "a linear move needs a non-zero direction, distance >= 0 and speed > 0"
            )
        start_time = self.world.time
        driven = line.started_at(self.T_world_palm_commanded())
        direction = driven.unit_direction
        p_start_measured = self.world.hand.T_world_palm()[:3, 3]

        cycles, contact, T_at_contact, palm_touched = 0, None, None, False
        if stop_on_contact:
            self.world.hand.palm_sensor()  # a touch latched before this move is not ours
        waypoints = driven.waypoints(self.control_period)
        for k, T_waypoint in enumerate(waypoints, start=1):
            q_previous = self.q_ik
            q_waypoint = self._track(T_waypoint)
            qd_waypoint = None
            if k < len(waypoints):
                qd_waypoint = self._bounded_velocity(
                    (q_waypoint - q_previous) / self.control_period
                )
            self.trajectory.set_target(q_waypoint, qd_waypoint)
            self.cycle()
            cycles += 1
            if each_cycle is not None:
                each_cycle()
            if stop_on_contact:
                reading = self.world.hand.palm_sensor()
                if reading.touched:
                    contact, palm_touched = reading.first_contact, reading.on_palm
                    T_at_contact = self.world.hand.T_world_palm()
                    self.trajectory.stop()
                    break
        cycles += self._cycles_until_rest()
        # Hold where the arm came to rest, and plan the next move from there.
        self.q_ik = self.trajectory.q.copy()
        T_end = self.world.hand.T_world_palm()
        travel_after = 0.0
        if T_at_contact is not None:
            travel_after = float((T_end[:3, 3] - T_at_contact[:3, 3]) @ direction)
        return LinearMoveResult(
            stopped_by_contact=contact is not None,
            first_contact=contact,
            palm_touched=palm_touched,
            T_world_palm_at_contact=T_at_contact,
            T_world_palm_end=T_end,
            travel=float((T_end[:3, 3] - p_start_measured) @ direction),
            travel_after_contact=travel_after,
            duration=self.world.time - start_time,
            cycles=cycles,
        )
