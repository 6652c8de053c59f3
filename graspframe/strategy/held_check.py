"""The held test (docs/method.md#held): one procedure and one set of criteria, for the
robot's grasps and the simulated human reference alike.

"Held": the object rises with a `lift_height` lift (at least `held_rise_fraction` of
it) and stays within `max_shift_in_hand` and `max_turn_in_hand_deg` of its pose in the
hand at the hold; then, while a force of `disturbance_fraction` of its weight pushes it
for `disturbance_time` along each of +x, -x, +y, -y, +z, -z (world, one after the
other), it stays within the same bounds of its pose in the hand after the lift.

`HeldTest` holds the criteria (defaults: the constants below and graspframe/common/defaults.py's
LIFT_HEIGHT and DISTURBANCE_FRACTION, the only place each is written) and runs the test
on the grasp in a world; `HeldVerdict` is what it found. A run passes one `HeldTest` to
the robot's execution and to the human reference, so both are judged alike.

Two tests are named (`held_test_named`): "graspframe", the test above (the default), and
"benchmark", the convention of the field's grasp benchmarks (DexGraspBench, Dexonomy):
gravity off (the object's weight cancelled by an equal upward force on its centroid), a
force equal to its weight along each of +x, -x, +y, -y, +z, -z for 2 s, failure past
5 cm or 15 deg of object motion in the hand. The benchmarks hold the object in free
space; here it stands on the table at the hold, so the hand first lifts it (gravity
off) clear of the table, and the lift must bring it along.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact
from graspframe.common.defaults import DISTURBANCE_FRACTION, LIFT_HEIGHT
from graspframe.common.errors import GraspframeError, InputError
from graspframe.common.transforms import inv_T, rotation_angle
from graspframe.hal.drivers import ObjectProbe, World
from graspframe.hal.objects import ObjectDescription

if TYPE_CHECKING:  # the arm's motion (IK, trajectories) only drives the lift; a run request
    # names its held test without it
    from graspframe.motion.arm_motion import ArmMotion

LIFT_SPEED = 0.05  # [m/s]
LIFT_SETTLE_TIME = 0.5  # [s] the hand stands still after the lift before it is judged
HELD_RISE_FRACTION = 0.8  # the object must rise by at least this part of the lift
MAX_SHIFT_IN_HAND = 0.02  # [m] largest displacement of the object in the palm frame
MAX_TURN_IN_HAND_DEG = 15.0  # [deg] largest rotation of the object in the palm frame
DISTURBANCE_TIME = 0.5  # [s] per direction
SAMPLE_PERIOD = 0.02  # [s] how often the object's pose in the hand is sampled
GRAVITY = 9.81  # [m/s^2] the simulated worlds' (an object's weight)
# The benchmark convention's criteria (DexGraspBench; Dexonomy).
BENCHMARK_MAX_SHIFT = 0.05  # [m]
BENCHMARK_MAX_TURN_DEG = 15.0  # [deg]
BENCHMARK_FORCE_FRACTION = 1.0  # of the object's weight
BENCHMARK_PUSH_TIME = 2.0  # [s] per direction
HELD_TEST_GRASPFRAME = "graspframe"
HELD_TEST_BENCHMARK = "benchmark"
HELD_TESTS = (HELD_TEST_GRASPFRAME, HELD_TEST_BENCHMARK)
DISTURBANCE_DIRECTIONS = {
    "+x": (1.0, 0.0, 0.0),
    "-x": (-1.0, 0.0, 0.0),
    "+y": (0.0, 1.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "+z": (0.0, 0.0, 1.0),
    "-z": (0.0, 0.0, -1.0),
}


@dataclass(frozen=True)
class InHandMotion:
    """How far the object moved in the palm frame from a reference pose: shift [m] and
    turn [deg] (the largest seen over the samples)."""

    shift: float
    turn_deg: float

    def to_dict(self) -> dict:
        return {"shift_mm": 1000.0 * self.shift, "turn_deg": self.turn_deg}

    def describe(self) -> str:
        return f"{1000 * self.shift:.0f} mm and {self.turn_deg:.0f} deg"


def in_hand_motion(
    T_palm_object_ref: NDArray[np.float64], samples: list[NDArray[np.float64]]
) -> InHandMotion:
    """The largest shift [m] and turn [deg] of the object in the palm frame over
    `samples` (T_palm_object poses), from the reference pose."""
    shift = max(float(np.linalg.norm(T[:3, 3] - T_palm_object_ref[:3, 3])) for T in samples)
    turn = max(math.degrees(rotation_angle(T[:3, :3], T_palm_object_ref[:3, :3])) for T in samples)
    return InHandMotion(shift, turn)


@dataclass(frozen=True)
class LiftResult:
    """object_rise: [m] object height gained; motion: the object's largest motion in the
    hand from the hold; held: both within bounds; contacts: the hand's contacts after it."""

    object_rise: float
    motion: InHandMotion
    held: bool
    contacts: list[Contact]


def object_probe(world: World) -> ObjectProbe:
    """The world's object: grasping and the held test need one."""
    if world.object is None:
        raise GraspframeError("this world has no object to grasp")
    return world.object


def T_palm_object(world: World) -> NDArray[np.float64]:
    """The object's pose in the palm frame now."""
    return inv_T(world.hand.T_world_palm()) @ object_probe(world).T_world_object()


@dataclass(frozen=True)
class HeldVerdict:
    """What the held test found.

    after_lift: the lift held; under_disturbance: the pushes held (None when they did not
    run: the lift failed, they were not asked for, or the backend cannot push, which
    `disturbance_skipped` says); failure: why it did not hold, in words (None: it held).
    object_rise [m], lift_height [m], lift_motion: the lift; disturbance: per direction
    ("+x", ...), the object's largest motion in the hand; fingers_after_lift: the real
    fingers touching after the lift. (result.json's outcome lists the fields in this
    order.)
    """

    after_lift: bool
    under_disturbance: bool | None
    failure: str | None
    object_rise: float = 0.0
    lift_height: float = LIFT_HEIGHT
    lift_motion: InHandMotion | None = None
    disturbance: Mapping[str, InHandMotion] = field(default_factory=dict)
    disturbance_skipped: str | None = None
    fingers_after_lift: tuple[str, ...] = ()
    held_test: str = HELD_TEST_GRASPFRAME  # which test judged: a name of HELD_TESTS

    @property
    def held(self) -> bool:
        return self.failure is None and self.after_lift

    def result_json(self) -> dict[str, Any]:
        """result.json's form of the verdict (a human reference's "human_held_test"):
        whether it held, and why not, without the measurements."""
        return {
            "held": self.held,
            "held_test": self.held_test,
            "held_after_lift": self.after_lift,
            "held_under_disturbance": self.under_disturbance,
            "failure": self.failure,
        }

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> HeldVerdict:
        """The verdict from its JSON values (graspframe.common.json_files.jsonable of one: every
        field, motions in [m] and [deg]), as a cached human reference keeps it."""
        pushes = data["disturbance"]
        return cls(
            after_lift=bool(data["after_lift"]),
            under_disturbance=data["under_disturbance"],
            failure=data["failure"],
            object_rise=float(data["object_rise"]),
            lift_height=float(data["lift_height"]),
            lift_motion=_motion_from_json(data["lift_motion"]),
            fingers_after_lift=tuple(data["fingers_after_lift"]),
            disturbance={
                d: InHandMotion(float(m["shift"]), float(m["turn_deg"])) for d, m in pushes.items()
            },
            disturbance_skipped=data["disturbance_skipped"],
            held_test=str(data.get("held_test", HELD_TEST_GRASPFRAME)),
        )


def _motion_from_json(data: Mapping[str, Any] | None) -> InHandMotion | None:
    return None if data is None else InHandMotion(float(data["shift"]), float(data["turn_deg"]))


@dataclass(frozen=True)
class HeldTest:
    """The held test's criteria (see the module docstring) and its procedure.

    disturb: push the object after a lift that held (False: the lift alone judges).
    gravity: False cancels the object's weight with an equal upward force on its
        centroid for the whole test (the benchmark convention).
    name: which test this is, a name of HELD_TESTS (the verdict carries it).
    """

    lift_height: float = LIFT_HEIGHT
    lift_speed: float = LIFT_SPEED
    lift_settle_time: float = LIFT_SETTLE_TIME
    held_rise_fraction: float = HELD_RISE_FRACTION
    max_shift_in_hand: float = MAX_SHIFT_IN_HAND
    max_turn_in_hand_deg: float = MAX_TURN_IN_HAND_DEG
    disturbance_fraction: float = DISTURBANCE_FRACTION
    disturbance_time: float = DISTURBANCE_TIME
    disturb: bool = True
    gravity: bool = True
    name: str = HELD_TEST_GRASPFRAME

    def within_bounds(self, motion: InHandMotion) -> bool:
        return motion.shift <= self.max_shift_in_hand and motion.turn_deg <= (
            self.max_turn_in_hand_deg
        )

    def key(self) -> tuple:
        """Every criterion the verdict depends on (for cache keys of stored verdicts)."""
        return (
            self.lift_height,
            self.lift_speed,
            self.lift_settle_time,
            self.held_rise_fraction,
            self.max_shift_in_hand,
            self.max_turn_in_hand_deg,
            self.disturbance_fraction,
            self.disturbance_time,
            tuple(DISTURBANCE_DIRECTIONS),
            self.disturb,
            *(() if self.gravity else ("gravity off",)),
        )

    def disturbance_force(self, obj: ObjectDescription) -> float:
        """[N] the push of the disturbance test on `obj`."""
        return self.disturbance_fraction * obj.mass * GRAVITY

    def weight_cancelled(self, obj: ObjectDescription) -> NDArray[np.float64]:
        """[N] the standing force on `obj` throughout the test: its weight upwards when
        gravity is off, nothing otherwise."""
        up = 0.0 if self.gravity else obj.mass * GRAVITY
        return np.array([0.0, 0.0, up])

    # -- the procedure ------------------------------------------------------------------

    def run(
        self,
        world: World,
        motion: ArmMotion,
        obj: ObjectDescription,
        after_lift: Callable[[LiftResult], None] = lambda _lifted: None,
    ) -> HeldVerdict:
        """The whole held test on the grasp now in `world`: the lift, then (when it held,
        the pushes are asked for and the backend can push) the pushes. `after_lift` hears
        of the lift before the pushes start. With gravity off the object's weight is
        cancelled from the start of the lift to the verdict."""
        if not self.gravity:
            try:
                object_probe(world).apply_force(self.weight_cancelled(obj))
            except NotImplementedError as exc:
                raise GraspframeError(
                    f"the {self.name} held test turns gravity off, which needs a backend "
                    f"that can push the object ({exc})"
                ) from None
        try:
            return self._judged(world, motion, obj, after_lift)
        finally:
            if not self.gravity:
                object_probe(world).apply_force(None)

    def _judged(
        self,
        world: World,
        motion: ArmMotion,
        obj: ObjectDescription,
        after_lift: Callable[[LiftResult], None],
    ) -> HeldVerdict:
        lifted = self.lift(world, motion)
        after_lift(lifted)
        lifted_verdict = HeldVerdict(
            after_lift=lifted.held,
            under_disturbance=None,
            failure=None,
            object_rise=lifted.object_rise,
            lift_height=self.lift_height,
            lift_motion=lifted.motion,
            fingers_after_lift=tuple(sorted({c.real_finger for c in lifted.contacts})),
            held_test=self.name,
        )
        if not lifted.held:
            failure = self.lift_failure(lifted.object_rise, lifted.motion)
            return replace(lifted_verdict, failure=failure, disturbance_skipped="the lift failed")
        if not self.disturb:
            return replace(lifted_verdict, disturbance_skipped="not asked for")
        if self.disturbance_fraction == 0.0:
            # a push of no force would pass every grasp: report it as not tested
            return replace(lifted_verdict, disturbance_skipped="disturbance fraction 0")
        try:
            pushed = self.push(world, motion, obj)
        except NotImplementedError as exc:
            return replace(lifted_verdict, disturbance_skipped=str(exc))
        slip = self.disturbance_failure(pushed)
        return replace(
            lifted_verdict, under_disturbance=slip is None, failure=slip, disturbance=pushed
        )

    def lift(self, world: World, motion: ArmMotion) -> LiftResult:
        """Raise the palm by lift_height straight up (the lift of strategy/segments.py),
        wait lift_settle_time, and judge whether the object came along."""
        # The segments need the arm's motion, which a run request names its test without.
        from graspframe.strategy.segments import lift_line

        T_palm_object_hold = T_palm_object(world)
        z_object_hold = object_probe(world).T_world_object()[2, 3]
        samples: list[NDArray[np.float64]] = []
        lift = lift_line(motion.T_world_palm_commanded(), self.lift_height, self.lift_speed)
        motion.follow(
            lift,
            stop_on_contact=False,
            each_cycle=lambda: samples.append(T_palm_object(world)),
        )
        settle_steps = round(self.lift_settle_time / world.timestep)
        sample_steps = max(1, round(SAMPLE_PERIOD / world.timestep))
        for _ in range(max(1, settle_steps // sample_steps)):
            motion.idle(sample_steps)
            samples.append(T_palm_object(world))
        rise = float(object_probe(world).T_world_object()[2, 3] - z_object_hold)
        moved = in_hand_motion(T_palm_object_hold, samples)
        held = rise >= self.held_rise_fraction * self.lift_height and self.within_bounds(moved)
        return LiftResult(rise, moved, held, world.hand.contacts())

    def push(
        self, world: World, motion: ArmMotion, obj: ObjectDescription
    ) -> dict[str, InHandMotion]:
        """Push the object with disturbance_fraction of its weight along each world axis
        in turn; per direction, its largest motion in the hand from its pose before the
        pushes. Raises NotImplementedError when the backend cannot push an object."""
        T_palm_object_ref = T_palm_object(world)
        force = self.disturbance_force(obj)
        check_every = max(1, round(SAMPLE_PERIOD / world.timestep))
        checks = max(1, round(self.disturbance_time / (check_every * world.timestep)))
        probe = object_probe(world)
        motion_by_direction: dict[str, InHandMotion] = {}
        standing = self.weight_cancelled(obj)
        for label, direction in DISTURBANCE_DIRECTIONS.items():
            probe.apply_force(standing + force * np.asarray(direction))
            samples = []
            for _ in range(checks):
                motion.idle(check_every)
                samples.append(T_palm_object(world))
            probe.apply_force(standing if not self.gravity else None)
            motion_by_direction[label] = in_hand_motion(T_palm_object_ref, samples)
        return motion_by_direction

    # -- verdicts in words --------------------------------------------------------------

    def first_slip(
        self, motion_by_direction: Mapping[str, InHandMotion]
    ) -> tuple[str, InHandMotion] | None:
        """The first direction in which the object left the bounds, with its motion."""
        return next(
            ((d, m) for d, m in motion_by_direction.items() if not self.within_bounds(m)), None
        )

    def lift_failure(self, object_rise: float, motion: InHandMotion | None) -> str:
        """Why a lift failed, in words."""
        moved = ""
        if motion is not None and not self.within_bounds(motion):
            moved = f"; it moved {motion.describe()} in the hand"
        return (
            f"the object slipped during the lift: it rose {round(1000 * object_rise)} mm "
            f"of the hand's {1000 * self.lift_height:.0f} mm{moved}"
        )

    def disturbance_failure(self, motion_by_direction: Mapping[str, InHandMotion]) -> str | None:
        """Why the disturbance test failed, in words (None when it held)."""
        slip = self.first_slip(motion_by_direction)
        if slip is None:
            return None
        direction, motion = slip
        return (
            f"the object slipped under the disturbance: pushed along {direction} with "
            f"{100 * self.disturbance_fraction:.0f} % of its weight"
            f"{'' if self.gravity else ' (gravity off)'} it moved "
            f"{motion.describe()} in the hand "
            f"(allowed {1000 * self.max_shift_in_hand:.0f} mm, "
            f"{self.max_turn_in_hand_deg:.0f} deg)"
        )


def held_test_words(held: HeldTest) -> str:
    """The test in a few words, e.g. "5 cm lift, pushes of 50 % of its weight"."""
    gravity = "" if held.gravity else ", gravity off"
    return (
        f"{held.lift_height * 100:g} cm lift, pushes of {held.disturbance_fraction * 100:.0f} % "
        f"of its weight for {held.disturbance_time:g} s each{gravity} "
        f"({held.name} held test: within {held.max_shift_in_hand * 1000:.0f} mm and "
        f"{held.max_turn_in_hand_deg:g} deg)"
    )


def held_test_named(
    name: str,
    lift_height: float = LIFT_HEIGHT,
    disturbance_fraction: float = DISTURBANCE_FRACTION,
) -> HeldTest:
    """The held test called `name` (HELD_TESTS): "graspframe" with the given lift and push,
    or "benchmark", the field's convention (its push is the object's weight: a
    `disturbance_fraction` other than the default is refused)."""
    if name == HELD_TEST_GRASPFRAME:
        return HeldTest(lift_height=lift_height, disturbance_fraction=disturbance_fraction)
    if name == HELD_TEST_BENCHMARK:
        if disturbance_fraction != DISTURBANCE_FRACTION:
            raise InputError(
                "the benchmark held test pushes with the object's whole weight; "
                "drop the disturbance fraction or use the graspframe held test"
            )
        return HeldTest(
            lift_height=lift_height,
            max_shift_in_hand=BENCHMARK_MAX_SHIFT,
            max_turn_in_hand_deg=BENCHMARK_MAX_TURN_DEG,
            disturbance_fraction=BENCHMARK_FORCE_FRACTION,
            disturbance_time=BENCHMARK_PUSH_TIME,
            gravity=False,
            name=HELD_TEST_BENCHMARK,
        )
    raise InputError(f"unknown held test {name!r}; held tests: {', '.join(HELD_TESTS)}")
