"""The method's grasp strategy (docs/method.md#the-grasp-strategy): the robot's grasp
policy for graspframe/strategy/execution.py.

Stages: open the hand in its preshape while the arm moves the palm to the via and the
pre-approach pose; approach along a (volar: until the first contact, correcting the goal
while that contact is not on the palm, then centring the object on the grasp centre from
where it touches the palm; non-volar: to the standoff goal, no feedback); close the hand
until it settles; hold. The held test and the pictures' moments at the hold and after
the lift follow in execution.py, the same for every policy. Every step is reported as an
event through `emit(kind, **data)`, `kind` one of the "execute.*" kinds declared in
graspframe/plugin_system/events.py.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import MotionError
from graspframe.common.grasps import PALM
from graspframe.common.transforms import inv_T
from graspframe.hal.descriptions import HandDescription
from graspframe.hal.drivers import World
from graspframe.hal.objects import ObjectDescription
from graspframe.motion.arm_motion import ArmMotion
from graspframe.motion.palm_line import PalmLine
from graspframe.plugin_system import events
from graspframe.strategy.execution import ExecutionLog, Grip
from graspframe.strategy.held_check import HeldTest
from graspframe.strategy.planner import GraspPlan
from graspframe.strategy.segments import PalmPath, approach_line, palm_path, retreat_line

# A cylinder's axis lies across the palm when its part in the palm plane is longer than
# this (the sine of its angle to the palm normal): then the palm contacts say nothing
# about where the cylinder's centre is along it.
AXIS_ACROSS_PALM = 0.5  # [-]


@dataclass(frozen=True)
class ExecutorParams:
    """The method's strategy's settings, each written here only. The held test's own
    settings are `HeldTest`'s."""

    alpha_start: float = 0.5  # [-] first weight of the contact point in the goal correction
    max_corrections: int = 4  # goal corrections of a volar approach (finger first, off-centre)
    # A palm touch further than this from the grasp centre (across the object's axis)
    # moves the goal by the offset and approaches again: a thin handle held 1 cm off its
    # grasp centre slips out of a Barrett wrap.
    centring_tolerance: float = 0.005  # [m]
    min_retreat: float = 0.03  # [m] shortest start of a corrected approach before its goal
    approach_speed: float = 0.05  # [m/s] non-volar approach, retreats, back-offs
    descent_speed: float = 0.10  # [m/s] via to pre-approach pose: twice the approach speed
    # The volar approach is a guarded move: at 5 cm/s its first touch knocked a 12 cm
    # handle over (the arm brakes within a few millimetres, the handle tips at 0.14 N) in
    # 2 of 6 runs of experiment B.
    guarded_approach_speed: float = 0.025  # [m/s]
    # A volar approach may go this far past its goal looking for the first contact: more
    # than the 5 cm object position error of experiment B.
    approach_overshoot: float = 0.07  # [m]
    close_time_limit: float = 2.0  # [s]
    close_min_time: float = 0.2  # [s] the fingers move at least this long before they may settle
    close_check_period: float = 0.05  # [s] how often the closing fingers' speed is measured
    settled_speed: float = 0.05  # [rad/s] the hand counts as closed when no joint moves faster
    hold_time: float = 0.5  # [s]


def planned_path(plan: GraspPlan, params: ExecutorParams, held: HeldTest | None = None) -> PalmPath:
    """The segments the strategy drives for `plan` (segments.py), with the held test's
    lift when `held` is given: what the executor drives and the path check checks."""
    approach_speed = params.guarded_approach_speed if plan.volar else params.approach_speed
    return palm_path(
        plan,
        params.descent_speed,
        approach_speed,
        params.approach_speed,
        None if held is None else held.lift_height,
        None if held is None else held.lift_speed,
    )


@dataclass(frozen=True)
class MethodStrategy:
    """The method's strategy for one plan: a `GraspPolicy` (execution.py)."""

    plan: GraspPlan
    hand: HandDescription
    obj: ObjectDescription
    params: ExecutorParams = ExecutorParams()

    def grasp(self, world: World, motion: ArmMotion, log: ExecutionLog) -> Grip:
        return _Strategy(self.plan, world, motion, self.hand, self.obj, self.params, log).run()


@dataclass
class _Strategy:
    """One execution of the strategy, stage by stage."""

    plan: GraspPlan
    world: World
    motion: ArmMotion
    hand: HandDescription
    obj: ObjectDescription
    p: ExecutorParams
    log: ExecutionLog

    def __post_init__(self) -> None:
        self.path = planned_path(self.plan, self.p)
        self.emit = self.log.emit

    def run(self) -> Grip:
        preshape = self.hand.preshape(self.plan.preshape)
        self._move_to_pre_approach(preshape.open_q)
        if self.plan.volar:
            corrections, palm_contact, goals = self._approach_volar()
            if palm_contact and self.path.back_off is not None:
                self._back_off()
        else:
            corrections, goals = 0, [self.plan.T_world_palm_goal[:3, 3].tolist()]
            palm_contact = self._approach_non_volar()
        self._close(preshape.closed_q)
        self.motion.idle(round(self.p.hold_time / self.world.timestep))
        goals_world = tuple((float(x), float(y), float(z)) for x, y, z in goals)
        return Grip(palm_contact, corrections, goals_world)

    # -- stages -------------------------------------------------------------------------

    def _move_to_pre_approach(
        self,
        open_q: Mapping[str, float],
        at_via: Callable[[], None] | None = None,
    ) -> None:
        """Open the hand while the arm moves the palm to the path's via, call `at_via`
        there (a strategy's look, which may shift the path), then descend to the
        pre-approach pose."""
        plan, motion = self.plan, self.motion
        self.world.hand.set_joint_targets(open_q)
        self.emit(events.EXECUTE_PRESHAPE, preshape=plan.preshape)
        duration = motion.move_palm_to(self.path.T_world_palm_via)
        if at_via is not None:
            at_via()
        descent = self.path.descent
        if descent is not None:
            duration += motion.follow(descent, stop_on_contact=False).duration
        self.emit(
            events.EXECUTE_PRE_APPROACH,
            duration=duration,
            T_world_palm=self.world.hand.T_world_palm(),
        )

    def _approach_non_volar(self) -> bool:
        """Straight to the standoff goal, no feedback; returns whether the palm touches."""
        approach = self.path.approach
        result = self.motion.follow(approach, stop_on_contact=False)
        self.emit(
            events.EXECUTE_APPROACH, travel=result.travel, stopped=False, cycles=result.cycles
        )
        self.log.snapshot(self.world, "approach end", self.world.hand.contacts())
        return any(c.real_finger == PALM for c in self.world.hand.contacts())

    def _approach_volar(self) -> tuple[int, bool, list[list[float]]]:
        """Approach until the first contact; correct while it is not on the palm.

        Returns (corrections, palm contact reached, goals tried)."""
        plan, motion, p, emit = self.plan, self.motion, self.p, self.emit
        approach = self.path.approach  # then the approach to each corrected goal
        T_goal = plan.T_world_palm_goal.copy()
        goals = [T_goal[:3, 3].tolist()]
        alpha, corrections = p.alpha_start, 0
        while True:
            result = motion.follow(approach.extended(p.approach_overshoot))
            emit(
                events.EXECUTE_APPROACH,
                travel=result.travel,
                stopped=result.stopped_by_contact,
                cycles=result.cycles,
            )
            contact = result.first_contact
            if contact is None:  # the move was not stopped by a contact
                emit(events.EXECUTE_NO_CONTACT, goal=T_goal[:3, 3])
                self.log.snapshot(self.world, "approach end", [])
                return corrections, False, goals
            emit(
                events.EXECUTE_FIRST_CONTACT,
                link=contact.link,
                real_finger=contact.real_finger,
                p_world=contact.p,
                on_palm=result.palm_touched,
            )
            centring = self._centring_shift() if result.palm_touched else None
            if result.palm_touched and centring is None:
                self.log.snapshot(self.world, "first contact", self.world.hand.contacts())
                return corrections, True, goals
            if corrections >= p.max_corrections:
                emit(events.EXECUTE_CORRECTIONS_EXHAUSTED, corrections=corrections)
                self.log.snapshot(self.world, "first contact", self.world.hand.contacts())
                return corrections, result.palm_touched, goals
            # Retreat along the approach line, move the goal, go again: towards a finger
            # contact (the method), or by the palm contact's offset from the grasp centre.
            self._retreat(max(result.travel, 0.0))
            p_goal_old = T_goal[:3, 3].copy()
            if centring is None:
                p_goal_new = p_goal_old + self._towards_contact(T_goal, contact.p, alpha)
                alpha = alpha**2
            else:
                p_goal_new = p_goal_old + centring
            # The object stands on the table: its height is known, only its place on the
            # table is not, so the goal keeps its height (a finger touching the top rim
            # of a can would otherwise lift the grasp off the can's middle).
            p_goal_new[2] = p_goal_old[2]
            T_goal[:3, 3] = p_goal_new
            corrections += 1
            emit(
                events.EXECUTE_CORRECTION,
                index=corrections,
                reason="finger first" if centring is None else "palm off centre",
                alpha=alpha if centring is None else None,
                p_contact=contact.p,
                goal_before=p_goal_old,
                goal_after=T_goal[:3, 3].copy(),
            )
            goals.append(T_goal[:3, 3].tolist())
            approach = self._to_corrected_start(T_goal, approach.speed, result.travel)

    def _retreat(self, distance: float) -> None:
        """Back along the approach by `distance` [m] from where the palm is."""
        retreat = retreat_line(
            self.plan, self.motion.T_world_palm_commanded(), distance, self.p.approach_speed
        )
        self.motion.follow(retreat, stop_on_contact=False)

    def _to_corrected_start(
        self, T_world_palm_goal: NDArray[np.float64], speed: float, retreated: float
    ) -> PalmLine:
        """Move to the start of the approach to a corrected goal: the pre-approach
        distance back from it, or, when the arm cannot reach that (a low goal near the
        arm's base), as far back as the hand just retreated. Returns that approach (at
        `speed` [m/s])."""
        try:
            approach = approach_line(
                self.plan, T_world_palm_goal, self.plan.pre_approach_distance, speed
            )
            self.motion.move_palm_to(approach.T_world_palm_start)
        except MotionError:
            d_start = max(retreated, self.p.min_retreat)
            approach = approach_line(self.plan, T_world_palm_goal, d_start, speed)
            self.motion.move_palm_to(approach.T_world_palm_start)
        return approach

    def _back_off(self) -> None:
        """Back the palm off the object it found by the plan's volar gap along the
        approach, so the object sits where the preshape's fingers close on it."""
        back_off = self.path.back_off
        assert back_off is not None  # only plans with a volar gap back off
        result = self.motion.follow(back_off, stop_on_contact=False)
        self.emit(events.EXECUTE_BACK_OFF, gap=back_off.distance, travel=-result.travel)

    def _close(self, closed_q: Mapping[str, float]) -> None:
        world = self.world
        world.hand.set_joint_targets(closed_q)
        names = list(closed_q)
        check_every = max(1, round(self.p.close_check_period / world.timestep))
        previous = world.hand.joint_positions()
        start = world.time
        # Move for at least the shortest closing time before testing for the stop.
        while world.time - start < self.p.close_time_limit:
            self.motion.idle(check_every)
            current = world.hand.joint_positions()
            speed = max(abs(current[n] - previous[n]) for n in names) / (
                check_every * world.timestep
            )
            previous = current
            if world.time - start > self.p.close_min_time and speed < self.p.settled_speed:
                break
        self.emit(
            events.EXECUTE_CLOSED, duration=world.time - start, q=dict(world.hand.joint_positions())
        )

    # -- helpers ------------------------------------------------------------------------

    def _towards_contact(
        self, T_world_palm_goal: NDArray[np.float64], p_contact: NDArray[np.float64], alpha: float
    ) -> NDArray[np.float64]:
        """[m] world shift of the palm goal that moves the grasp centre towards a finger
        contact: the method's p <- alpha * p_c + (1 - alpha) * p, with p the point where
        the hand holds the object (the preshape's grasp centre at the goal; the palm
        centre for a hand that holds objects there). Along the approach the approach
        itself finds the object, so only the shift across it is kept."""
        R_world_palm, p_world_palm = T_world_palm_goal[:3, :3], T_world_palm_goal[:3, 3]
        p_grasp_centre = R_world_palm @ self.plan.p_palm_object + p_world_palm
        shift = alpha * (np.asarray(p_contact) - p_grasp_centre)
        a = self.plan.a_world / np.linalg.norm(self.plan.a_world)
        return shift - (shift @ a) * a

    def _centring_shift(self) -> NDArray[np.float64] | None:
        """[m] world shift of the palm goal that puts the object's centre over the plan's
        grasp centre, judged from where the object touches the palm; None when it is
        within the centring tolerance.

        A convex object resting on the flat palm touches it right below its centre, so
        the mean palm contact (in the palm plane) is where the object's centre is. Along
        a cylinder's axis the contacts say nothing about its centre (and nothing needs
        centring), so that component is dropped; so is the vertical one."""
        palm_contacts = [c for c in self.world.hand.contacts() if c.real_finger == PALM]
        if not palm_contacts:
            return None
        T_world_palm = self.world.hand.T_world_palm()
        T_palm_world = inv_T(T_world_palm)
        p_palm_contacts = np.mean(
            [T_palm_world[:3, :3] @ c.p + T_palm_world[:3, 3] for c in palm_contacts], axis=0
        )
        offset_palm = np.array([*(p_palm_contacts[:2] - self.plan.p_palm_object[:2]), 0.0])
        if self.obj.shape == "cylinder":
            axis_palm = inv_T(self.plan.T_object_palm)[:3, :3] @ np.array([0.0, 0.0, 1.0])
            axis_palm[2] = 0.0
            if np.linalg.norm(axis_palm) > AXIS_ACROSS_PALM:
                u = axis_palm / np.linalg.norm(axis_palm)
                offset_palm -= (offset_palm @ u) * u
        shift_world = T_world_palm[:3, :3] @ offset_palm
        shift_world[2] = 0.0  # the object's height is known (it stands on the table)
        if np.linalg.norm(shift_world) <= self.p.centring_tolerance:
            return None
        return shift_world
