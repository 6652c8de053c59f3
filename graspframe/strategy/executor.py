"""The executor: carry out a GraspPlan through the driver interfaces (METHOD.md 4.3-4.5).

Sequence: open the hand in its preshape while the arm moves the palm to the pre-approach
pose; approach along a (volar: until the first contact, correcting the goal while that
contact is not on the palm; non-volar: to the standoff goal, no feedback); close the hand;
hold; lift. Every step is reported as an event through `emit(kind, **data)`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from graspframe.contacts import Contact
from graspframe.errors import GraspframeError, MotionError
from graspframe.hal.descriptions import HandDescription
from graspframe.hal.drivers import World
from graspframe.motion.arm_motion import ArmMotion
from graspframe.strategy.planner import GraspPlan

ALPHA_START = 0.5  # [-] first weight of the contact point in the goal correction
MAX_CORRECTIONS = 4
APPROACH_SPEED = 0.05  # [m/s]
# A volar approach may go this far past its goal looking for the first contact: more
# than the 5 cm object position error of experiment B.
APPROACH_OVERSHOOT = 0.07  # [m]
CLOSE_TIME_LIMIT = 2.0  # [s]
SETTLED_SPEED = 0.05  # [rad/s] the hand counts as closed when no joint moves faster
HOLD_TIME = 0.5  # [s]
LIFT_HEIGHT = 0.05  # [m]
LIFT_SPEED = 0.05  # [m/s]
HELD_FRACTION = 0.8  # the object is held if it rose by at least this part of the lift
MIN_FINGERS = 2  # real fingers (the palm counts as one) that must touch for a grasp


@dataclass(frozen=True)
class ExecutorParams:
    """alpha_start, max_corrections: the volar correction loop (METHOD.md 4.4);
    speeds [m/s], distances [m], times [s]."""

    alpha_start: float = ALPHA_START
    max_corrections: int = MAX_CORRECTIONS
    approach_speed: float = APPROACH_SPEED
    approach_overshoot: float = APPROACH_OVERSHOOT
    close_time_limit: float = CLOSE_TIME_LIMIT
    hold_time: float = HOLD_TIME
    lift_height: float = LIFT_HEIGHT
    lift_speed: float = LIFT_SPEED


@dataclass
class GraspOutcome:
    """What happened: contacts at the hold (world frame), the object, the corrections.

    held_after_lift: the object rose with the hand by at least HELD_FRACTION of the lift.
    object_rise: [m] object height gained during the lift.
    """

    contacts: list[Contact]
    T_world_object_at_hold: NDArray[np.float64]
    corrections: int
    palm_contact: bool
    held_after_lift: bool
    object_rise: float
    fingers_after_lift: list[str]
    lift_height: float
    goals: list[list[float]] = field(default_factory=list)
    aborted: str | None = None

    @property
    def touching_fingers(self) -> list[str]:
        return sorted({c.real_finger for c in self.contacts})

    @property
    def success(self) -> bool:
        """At least MIN_FINGERS real fingers touched and the object was held in the lift."""
        return self.failure_reason is None

    @property
    def failure_reason(self) -> str | None:
        """Why the grasp failed, in words (None when it succeeded)."""
        if self.aborted:
            return self.aborted
        fingers = self.touching_fingers
        if not fingers:
            return "no real finger touched the object when the hand closed"
        if len(fingers) < MIN_FINGERS:
            return f"only {', '.join(fingers)} touched the object; a grasp needs {MIN_FINGERS}"
        if not self.held_after_lift:
            return (
                f"the object slipped during the lift: it rose {1000 * self.object_rise:.0f} mm "
                f"of the hand's {1000 * self.lift_height:.0f} mm"
            )
        return None


Emit = Callable[..., None]


def _close_hand(world: World, closed_q, time_limit: float, emit: Emit) -> None:
    world.hand.set_joint_targets(closed_q)
    names = list(closed_q)
    check_every = max(1, round(0.05 / world.timestep))
    previous = world.hand.joint_positions()
    start = world.time
    # Move for at least the shortest closing time before testing for the stop.
    while world.time - start < time_limit:
        world.step(check_every)
        current = world.hand.joint_positions()
        speed = max(abs(current[n] - previous[n]) for n in names) / (check_every * world.timestep)
        previous = current
        if world.time - start > 0.2 and speed < SETTLED_SPEED:
            break
    emit("execute.closed", duration=world.time - start, q=dict(world.hand.joint_positions()))


def _approach_volar(
    plan: GraspPlan, motion: ArmMotion, hand: HandDescription, p: ExecutorParams, emit: Emit
) -> tuple[int, bool, list[list[float]]]:
    """Approach until the first contact; correct while it is not on the palm.

    Returns (corrections, palm contact reached, goals tried)."""
    a = plan.a_world
    d_pre = plan.pre_approach_distance
    T_goal = plan.T_world_palm_goal.copy()
    goals = [T_goal[:3, 3].tolist()]
    alpha, corrections = p.alpha_start, 0
    while True:
        result = motion.move_palm_linear(a, d_pre + p.approach_overshoot, p.approach_speed)
        emit(
            "execute.approach",
            travel=result.travel,
            stopped=result.stopped_by_contact,
            cycles=result.cycles,
        )
        if not result.stopped_by_contact:
            emit("execute.no_contact", goal=T_goal[:3, 3])
            return corrections, False, goals
        contact = result.first_contact
        emit(
            "execute.first_contact",
            link=contact.link,
            real_finger=contact.real_finger,
            p_world=contact.p_world,
            on_palm=result.palm_touched,
        )
        if result.palm_touched:
            return corrections, True, goals
        if corrections >= p.max_corrections:
            emit("execute.corrections_exhausted", corrections=corrections)
            return corrections, False, goals
        # Retreat along the approach line, move the goal towards the contact, go again.
        motion.move_palm_linear(
            -a, max(result.travel, 0.0), p.approach_speed, stop_on_contact=False
        )
        p_goal_old = T_goal[:3, 3].copy()
        T_goal[:3, 3] = alpha * contact.p_world + (1.0 - alpha) * p_goal_old
        corrections += 1
        emit(
            "execute.correction",
            index=corrections,
            alpha=alpha,
            p_contact=contact.p_world,
            goal_before=p_goal_old,
            goal_after=T_goal[:3, 3].copy(),
        )
        goals.append(T_goal[:3, 3].tolist())
        alpha = alpha**2
        T_pre = T_goal.copy()
        T_pre[:3, 3] -= d_pre * a
        motion.move_palm_to(T_pre)


def execute_plan(
    plan: GraspPlan,
    world: World,
    motion: ArmMotion,
    hand: HandDescription,
    params: ExecutorParams | None = None,
    emit: Emit | None = None,
) -> GraspOutcome:
    """Execute `plan` on `world` (hand on an arm); see the module docstring.

    When the arm cannot carry the plan out (a pose out of reach, a line through a
    singularity) the grasp is aborted where it stands and the outcome says why.
    """
    p = params or ExecutorParams()
    emit = emit or (lambda kind, **data: None)
    if world.object is None:
        raise GraspframeError("executing a grasp needs a world with an object")
    try:
        return _execute(plan, world, motion, hand, p, emit)
    except MotionError as exc:
        emit("execute.aborted", reason=str(exc))
        return GraspOutcome(
            contacts=world.hand.contacts(),
            T_world_object_at_hold=world.object.T_world_object(),
            corrections=0,
            palm_contact=False,
            held_after_lift=False,
            object_rise=0.0,
            fingers_after_lift=[],
            lift_height=p.lift_height,
            aborted=f"the arm cannot carry out the plan: {exc}",
        )


def _execute(plan, world, motion, hand, p: ExecutorParams, emit: Emit) -> GraspOutcome:
    preshape = hand.preshape(plan.preshape)

    world.hand.set_joint_targets(preshape.open_q)
    emit("execute.preshape", preshape=preshape.name)
    duration = motion.move_palm_to(plan.T_world_palm_via)
    descent = plan.T_world_palm_via[2, 3] - plan.T_world_palm_pre[2, 3]
    if descent > 0:
        down = np.array([0.0, 0.0, -1.0])
        duration += motion.move_palm_linear(
            down, descent, p.approach_speed * 2, stop_on_contact=False
        ).duration
    emit("execute.pre_approach", duration=duration, T_world_palm=world.hand.T_world_palm())

    if plan.volar:
        corrections, palm_contact, goals = _approach_volar(plan, motion, hand, p, emit)
    else:
        result = motion.move_palm_linear(
            plan.a_world, plan.pre_approach_distance, p.approach_speed, stop_on_contact=False
        )
        emit("execute.approach", travel=result.travel, stopped=False, cycles=result.cycles)
        corrections, goals = 0, [plan.T_world_palm_goal[:3, 3].tolist()]
        palm_contact = world.hand.palm_sensor().on_palm

    _close_hand(world, preshape.closed_q, p.close_time_limit, emit)
    world.step(round(p.hold_time / world.timestep))
    contacts = world.hand.contacts()
    T_world_object_at_hold = world.object.T_world_object()
    emit(
        "execute.hold",
        fingers=sorted({c.real_finger for c in contacts}),
        n_contacts=len(contacts),
        contacts=contacts,
    )

    up = np.array([0.0, 0.0, 1.0])
    motion.move_palm_linear(up, p.lift_height, p.lift_speed, stop_on_contact=False)
    world.step(round(p.hold_time / world.timestep))
    rise = float(world.object.T_world_object()[2, 3] - T_world_object_at_hold[2, 3])
    fingers_after = sorted({c.real_finger for c in world.hand.contacts()})
    held = rise >= HELD_FRACTION * p.lift_height
    emit("execute.lift", object_rise=rise, held=held, fingers=fingers_after)
    return GraspOutcome(
        contacts=contacts,
        T_world_object_at_hold=T_world_object_at_hold,
        corrections=corrections,
        palm_contact=palm_contact,
        held_after_lift=held,
        object_rise=rise,
        fingers_after_lift=fingers_after,
        lift_height=p.lift_height,
        goals=goals,
    )
