"""The held test (docs/method.md#held), shared by the robot executor and the simulated
human reference: lift the hand, then push the object.

"Held": the object rises with a LIFT_HEIGHT lift (at least HELD_RISE_FRACTION of it) and
stays within MAX_SHIFT_IN_HAND and MAX_TURN_IN_HAND_DEG of its pose in the hand at the
hold; then, while a force of DISTURBANCE_FRACTION of its weight pushes it for
DISTURBANCE_TIME along each of +x, -x, +y, -y, +z, -z (world, one after the other), it
stays within the same bounds of its pose in the hand after the lift.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.contacts import Contact
from graspframe.errors import GraspframeError
from graspframe.hal.drivers import ObjectProbe, World
from graspframe.hal.objects import ObjectDescription
from graspframe.motion.arm_motion import ArmMotion
from graspframe.transforms import inv_T, rotation_angle

LIFT_HEIGHT = 0.05  # [m]
LIFT_SPEED = 0.05  # [m/s]
SETTLE_TIME = 0.5  # [s] the hand stands still after the lift before it is judged
HELD_RISE_FRACTION = 0.8  # the object must rise by at least this part of the lift
MAX_SHIFT_IN_HAND = 0.02  # [m] largest displacement of the object in the palm frame
MAX_TURN_IN_HAND_DEG = 15.0  # [deg] largest rotation of the object in the palm frame
DISTURBANCE_FRACTION = 0.5  # of the object's weight
DISTURBANCE_TIME = 0.5  # [s] per direction
GRAVITY = 9.81  # [m/s^2]
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

    @property
    def within_bounds(self) -> bool:
        return self.shift <= MAX_SHIFT_IN_HAND and self.turn_deg <= MAX_TURN_IN_HAND_DEG

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


def lift(
    world: World,
    motion: ArmMotion,
    lift_height: float = LIFT_HEIGHT,
    lift_speed: float = LIFT_SPEED,
    settle_time: float = SETTLE_TIME,
) -> LiftResult:
    """Raise the palm by lift_height [m] straight up, wait settle_time [s], and judge
    whether the object came along."""
    T_palm_object_hold = T_palm_object(world)
    z_object_hold = object_probe(world).T_world_object()[2, 3]
    samples: list[NDArray[np.float64]] = []
    motion.move_palm_linear(
        np.array([0.0, 0.0, 1.0]),
        lift_height,
        lift_speed,
        stop_on_contact=False,
        each_cycle=lambda: samples.append(T_palm_object(world)),
    )
    settle_steps = round(settle_time / world.timestep)
    for _ in range(max(1, settle_steps // 10)):
        world.step(10)
        samples.append(T_palm_object(world))
    rise = float(object_probe(world).T_world_object()[2, 3] - z_object_hold)
    moved = in_hand_motion(T_palm_object_hold, samples)
    held = rise >= HELD_RISE_FRACTION * lift_height and moved.within_bounds
    return LiftResult(rise, moved, held, world.hand.contacts())


def disturb(world: World, obj: ObjectDescription) -> dict[str, InHandMotion]:
    """Push the object with DISTURBANCE_FRACTION of its weight along each world axis in
    turn; per direction, its largest motion in the hand from its pose before the pushes.

    Raises NotImplementedError when the backend cannot push an object."""
    T_palm_object_ref = T_palm_object(world)
    force = disturbance_force(obj)
    check_every = max(1, round(0.02 / world.timestep))
    checks = max(1, round(DISTURBANCE_TIME / (check_every * world.timestep)))
    probe = object_probe(world)
    motion_by_direction: dict[str, InHandMotion] = {}
    for label, direction in DISTURBANCE_DIRECTIONS.items():
        probe.apply_force(force * np.asarray(direction))
        samples = []
        for _ in range(checks):
            world.step(check_every)
            samples.append(T_palm_object(world))
        probe.apply_force(None)
        motion_by_direction[label] = in_hand_motion(T_palm_object_ref, samples)
    return motion_by_direction


@dataclass(frozen=True)
class HeldVerdict:
    """The outcome of `run`.

    under_disturbance: None when the disturbance test did not run (the lift failed, or
    the backend cannot push). failure: why it did not hold, in words (None: it held).
    """

    after_lift: bool
    under_disturbance: bool | None
    failure: str | None

    @property
    def held(self) -> bool:
        return self.failure is None and self.after_lift

    def to_dict(self) -> dict:
        return {
            "held": self.held,
            "held_after_lift": self.after_lift,
            "held_under_disturbance": self.under_disturbance,
            "failure": self.failure,
        }

    @classmethod
    def from_dict(cls, data: dict) -> HeldVerdict:
        return cls(bool(data["held_after_lift"]), data["held_under_disturbance"], data["failure"])


def run(world: World, motion: ArmMotion, obj: ObjectDescription) -> HeldVerdict:
    """The whole held test on the grasp now in `world`: the lift, then (when it held and
    the backend can push) the disturbance."""
    lifted = lift(world, motion)
    if not lifted.held:
        failure = lift_failure(lifted.object_rise, LIFT_HEIGHT, lifted.motion)
        return HeldVerdict(after_lift=False, under_disturbance=None, failure=failure)
    try:
        pushed = disturb(world, obj)
    except NotImplementedError:
        return HeldVerdict(after_lift=True, under_disturbance=None, failure=None)
    slip = disturbance_failure(pushed)
    return HeldVerdict(after_lift=True, under_disturbance=slip is None, failure=slip)


def criteria() -> tuple:
    """Every constant the verdict depends on (for cache keys of stored verdicts)."""
    return (
        LIFT_HEIGHT,
        LIFT_SPEED,
        SETTLE_TIME,
        HELD_RISE_FRACTION,
        MAX_SHIFT_IN_HAND,
        MAX_TURN_IN_HAND_DEG,
        DISTURBANCE_FRACTION,
        DISTURBANCE_TIME,
        tuple(DISTURBANCE_DIRECTIONS),
    )


def disturbance_force(obj: ObjectDescription) -> float:
    """[N] the push of the disturbance test on `obj`."""
    return DISTURBANCE_FRACTION * obj.mass * GRAVITY


def first_slip(motion_by_direction: dict[str, InHandMotion]) -> tuple[str, InHandMotion] | None:
    """The first direction in which the object left the bounds, with its motion."""
    return next(((d, m) for d, m in motion_by_direction.items() if not m.within_bounds), None)


def lift_failure(object_rise: float, lift_height: float, motion: InHandMotion | None) -> str:
    """Why a lift failed, in words."""
    moved = ""
    if motion is not None and not motion.within_bounds:
        moved = f"; it moved {motion.describe()} in the hand"
    return (
        f"the object slipped during the lift: it rose {1000 * object_rise:.0f} mm "
        f"of the hand's {1000 * lift_height:.0f} mm{moved}"
    )


def disturbance_failure(motion_by_direction: dict[str, InHandMotion]) -> str | None:
    """Why the disturbance test failed, in words (None when it held)."""
    slip = first_slip(motion_by_direction)
    if slip is None:
        return None
    direction, motion = slip
    return (
        f"the object slipped under the disturbance: pushed along {direction} with "
        f"{100 * DISTURBANCE_FRACTION:.0f} % of its weight it moved {motion.describe()} "
        "in the hand "
        f"(allowed {1000 * MAX_SHIFT_IN_HAND:.0f} mm, {MAX_TURN_IN_HAND_DEG:.0f} deg)"
    )
