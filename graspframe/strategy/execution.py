"""Executing a grasp: one procedure for the robot's runs, the human reference and the
hand-alone checks.

`execute` builds the world from its `WorldConfig` in a backend, puts an `ArmMotion` on
it (the arm, or the floating base of a hand alone) and runs `run_policy`: the grasp
policy brings the hand to the hold (the robot: the method's strategy,
graspframe/strategy/method.py; the human reference: its open-loop closing,
graspframe/strategy/human_reference.py), then the one held test (held_check.py) judges
the grasp. An `ExecutionLog` goes along: observers hear every step through its
`emit(kind, **data)` (the "execute.*" kinds of graspframe/plugin_system/events.py), and it keeps the
`Moment`s pictures are drawn from (the policy's own, then "hold" and "after lift").
Every control cycle the measured joints are checked against the model's limits
(motion/joint_limits.py): a joint past its limit is reported (execute.joint_limit), and
the execution keeps each joint's largest excess.

A policy that the arm cannot carry out (a pose out of reach, a line through a
singularity: `MotionError`) ends the grasp where it stands; the outcome says why.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact
from graspframe.common.errors import MotionError
from graspframe.hal.descriptions import joints_by_name
from graspframe.hal.drivers import Backend, World, WorldConfig
from graspframe.hal.objects import ObjectDescription
from graspframe.motion.arm_motion import ArmMotion
from graspframe.motion.joint_limits import JointLimitMonitor, JointLimitReport
from graspframe.plugin_system import events
from graspframe.strategy import held_check
from graspframe.strategy.held_check import HeldTest, HeldVerdict, InHandMotion, LiftResult

MIN_FINGERS = 2  # real fingers (the palm counts as one) that must touch for a grasp

# emit(kind: EventKind, **payload): reports one event of a declared kind.
Emit = Callable[..., None]


@dataclass(frozen=True)
class Grip:
    """How a policy brought the hand to the hold: whether the palm touched the object,
    the goal corrections it made, and the palm goals it tried [m] (world frame).
    (result.json's outcome lists the fields in this order.)"""

    palm_contact: bool = False
    corrections: int = 0
    goals: tuple[tuple[float, float, float], ...] = ()


@dataclass(frozen=True)
class Moment:
    """The robot, the object and the contacts at one moment of a grasp, for pictures.

    q_arm: [rad] the arm's joints in its `joint_names` order (the floating base's for a
    hand alone); q_hand: [rad or m] hand joints by name; poses in the world frame;
    contacts in the world frame.
    """

    label: str
    q_arm: NDArray[np.float64] | None
    q_hand: Mapping[str, float]
    T_world_palm: NDArray[np.float64]
    T_world_object: NDArray[np.float64]
    contacts: tuple[Contact, ...]


@dataclass
class ExecutionLog:
    """What an execution reports as it goes: events for the observers (`emit`) and the
    moments it keeps for pictures (`snapshot`)."""

    emit: Emit = field(default=lambda kind, **data: None)
    moments: list[Moment] = field(default_factory=list)

    def snapshot(self, world: World, label: str, contacts: list[Contact]) -> None:
        """Keep the robot's joints, the object and `contacts` now, and tell observers."""
        moment = Moment(
            label=label,
            q_arm=None if world.arm is None else world.arm.joint_positions(),
            q_hand=world.hand.joint_positions(),
            T_world_palm=world.hand.T_world_palm(),
            T_world_object=held_check.object_probe(world).T_world_object(),
            contacts=tuple(contacts),
        )
        self.moments.append(moment)
        self.emit(
            events.EXECUTE_SNAPSHOT,
            label=moment.label,
            q_arm=moment.q_arm,
            q_hand=moment.q_hand,
            T_world_palm=moment.T_world_palm,
            T_world_object=moment.T_world_object,
            contacts=list(moment.contacts),
        )


class GraspPolicy(Protocol):
    """Brings the hand from wherever the world starts to the hold (closed on the object,
    settled), reporting to `log`; the held test follows."""

    def grasp(self, world: World, motion: ArmMotion, log: ExecutionLog) -> Grip: ...


@dataclass(frozen=True)
class GraspOutcome:
    """What happened: contacts at the hold (world frame), the object's pose then, how the
    policy got there, and the held test's verdict (None when the grasp was aborted:
    `aborted` says why, and lift_height_requested [m] and held_test_requested are the
    lift and the test that would have judged it)."""

    contacts: list[Contact]
    T_world_object_at_hold: NDArray[np.float64]
    grip: Grip
    held: HeldVerdict | None
    aborted: str | None = None
    lift_height_requested: float = held_check.LIFT_HEIGHT
    held_test_requested: str = held_check.HELD_TEST_GRASPFRAME

    @property
    def verdict(self) -> HeldVerdict:
        """The held test's verdict; for an aborted grasp, the verdict of a test that did
        not run (not held, nothing measured, the requested lift height)."""
        if self.held is not None:
            return self.held
        return HeldVerdict(
            False,
            None,
            None,
            lift_height=self.lift_height_requested,
            held_test=self.held_test_requested,
        )

    @property
    def touching_fingers(self) -> list[str]:
        return sorted({c.real_finger for c in self.contacts})

    @property
    def corrections(self) -> int:
        return self.grip.corrections

    @property
    def palm_contact(self) -> bool:
        return self.grip.palm_contact

    @property
    def goals(self) -> list[list[float]]:
        return [list(goal) for goal in self.grip.goals]

    @property
    def held_after_lift(self) -> bool:
        return self.verdict.after_lift

    @property
    def held_under_disturbance(self) -> bool | None:
        return self.verdict.under_disturbance

    @property
    def object_rise(self) -> float:
        return self.verdict.object_rise

    @property
    def lift_height(self) -> float:
        return self.verdict.lift_height

    @property
    def lift_motion(self) -> InHandMotion | None:
        return self.verdict.lift_motion

    @property
    def fingers_after_lift(self) -> list[str]:
        return list(self.verdict.fingers_after_lift)

    @property
    def disturbance(self) -> Mapping[str, InHandMotion]:
        return self.verdict.disturbance

    @property
    def disturbance_skipped(self) -> str | None:
        return self.verdict.disturbance_skipped

    @property
    def success(self) -> bool:
        """Enough real fingers touched and the held test passed."""
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
        assert self.held is not None  # an outcome that was not aborted was judged
        return self.held.failure


@dataclass(frozen=True)
class Execution:
    """An executed grasp: its outcome, its moments (the robot's joints, the object and
    the contacts, for pictures) in the order they happened, and the joints that passed
    their model limits."""

    outcome: GraspOutcome
    moments: tuple[Moment, ...] = ()
    joint_limits: JointLimitReport = field(default_factory=JointLimitReport)


def execute(
    backend: Backend,
    config: WorldConfig,
    policy: GraspPolicy,
    held: HeldTest,
    emit: Emit | None = None,
    on_world: Callable[[World], None] | None = None,
    on_cycle: Callable[[ArmMotion], None] | None = None,
) -> Execution:
    """Build the world of `config` in `backend`, grasp with `policy` on the mounted robot
    (`config.robot`: the arm, or the floating base of a hand alone), judge the grasp
    with `held`; the world is released afterwards.

    on_world: hears of the world as soon as it is built (to read its clock);
    on_cycle: called every control cycle of the motion.
    """
    if config.robot is None:
        raise ValueError("execute needs the mounted robot (config.robot)")
    if config.object is None:
        raise ValueError("execute needs an object to grasp (config.object)")
    report = emit or (lambda kind, **data: None)
    monitor = JointLimitMonitor(config.robot.model)

    def emit_noting_stage(kind: events.EventKind, **data: Any) -> None:
        # A snapshot is taken within a stage, a joint-limit report is no stage.
        if kind not in (events.EXECUTE_SNAPSHOT, events.EXECUTE_JOINT_LIMIT):
            monitor.stage = kind.name
        report(kind, **data)

    log = ExecutionLog(emit_noting_stage)
    arm_joint_names = config.robot.arm.joint_names
    with backend.create_world(config) as world:
        if on_world is not None:
            on_world(world)

        def each_cycle(motion: ArmMotion) -> None:
            check_joint_limits(world, arm_joint_names, monitor, log.emit)
            if on_cycle is not None:
                on_cycle(motion)

        motion = ArmMotion(world, config.robot, config.T_world_arm_base, on_cycle=each_cycle)
        outcome = run_policy(world, motion, policy, config.object, held, log)
    return Execution(outcome, tuple(log.moments), monitor.report())


def check_joint_limits(
    world: World, arm_joint_names: tuple[str, ...], monitor: JointLimitMonitor, emit: Emit
) -> None:
    """Give `monitor` the measured joints now (the arm's, the hand's and its followers');
    report each joint that has just passed its limit by more than the tolerance."""
    assert world.arm is not None  # execute moves the hand with an arm or the floating base
    q_hand = {**world.hand.joint_positions(), **world.hand.follower_positions()}
    q_by_joint = joints_by_name(arm_joint_names, world.arm.joint_positions(), q_hand)
    for excess in monitor.check(world.time, q_by_joint):
        emit(
            events.EXECUTE_JOINT_LIMIT,
            joint=excess.joint,
            position=excess.position,
            lower=excess.limit.lower,
            upper=excess.limit.upper,
            excess=excess.excess,
        )


def run_policy(
    world: World,
    motion: ArmMotion,
    policy: GraspPolicy,
    obj: ObjectDescription,
    held: HeldTest,
    log: ExecutionLog | None = None,
) -> GraspOutcome:
    """Grasp with `policy` in an existing world, then judge the grasp with `held`: the
    procedure of `execute`, for callers that hold their own world."""
    log = log or ExecutionLog()
    emit = log.emit
    probe = held_check.object_probe(world)  # refuses a world without an object
    try:
        grip = policy.grasp(world, motion, log)
    except MotionError as exc:
        emit(events.EXECUTE_ABORTED, reason=str(exc))
        return GraspOutcome(
            contacts=world.hand.contacts(),
            T_world_object_at_hold=probe.T_world_object(),
            grip=Grip(),
            held=None,
            aborted=f"the arm cannot carry out the plan: {exc}",
            lift_height_requested=held.lift_height,
            held_test_requested=held.name,
        )
    contacts = world.hand.contacts()
    T_world_object_at_hold = probe.T_world_object()
    emit(
        events.EXECUTE_HOLD,
        fingers=sorted({c.real_finger for c in contacts}),
        n_contacts=len(contacts),
        contacts=contacts,
    )
    log.snapshot(world, "hold", contacts)

    def after_lift(lifted: LiftResult) -> None:
        emit(
            events.EXECUTE_LIFT,
            object_rise=lifted.object_rise,
            held=lifted.held,
            fingers=sorted({c.real_finger for c in lifted.contacts}),
            **lifted.motion.to_dict(),
        )
        log.snapshot(world, "after lift", lifted.contacts)

    verdict = held.run(world, motion, obj, after_lift)
    if verdict.disturbance:
        emit(
            events.EXECUTE_DISTURBANCE,
            force=held.disturbance_force(obj),
            held=verdict.under_disturbance,
            motion={d: m.to_dict() for d, m in verdict.disturbance.items()},
        )
    elif verdict.after_lift and held.disturb:  # the backend cannot push
        emit(events.EXECUTE_DISTURBANCE, skipped=verdict.disturbance_skipped)
    return GraspOutcome(contacts, T_world_object_at_hold, grip, verdict)
