"""The hand's joint controller: motor setpoints, controller couplings and their breakaway.

Any backend whose hand joints are position drives can use it: the backend reads the
measured joint positions and velocities, calls `HandController.update` before every step
and sends the returned targets to its drives.

Each joint's setpoint (the motor position) moves towards its command at the joint's
velocity limit, as independent finger motors do (the Barrett's). A hand whose
controller interpolates postures (`HandDescription.synchronised_closing`) moves its
setpoints in a straight line in joint space instead: every joint arrives at its
command when the slowest one does at its velocity limit. Its fingers then close along
the path the planner's kinematic closing follows (hand_geometry.py: open to closed, one
fraction for every joint), and a finger with a short way to go does not reach the
object long before the others and push it away. Closing means increasing a leader joint's
angle. For a controller coupling (`Coupling.in_model` False) the follower's target is
the coupling of the leader's motor position. With a breakaway torque (Barrett
TorqueSwitch), once the leader's drive torque exceeds it while closing, the leader is
held where it is and only the follower keeps following the motor; commanding the leader
back below the held angle releases it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from graspframe.common.errors import GraspframeError, UnknownNameError
from graspframe.hal.descriptions import DriveGains, HandDescription

# While a breakaway holds a leader joint, its drive is this much stiffer (the Barrett's
# proximal link is held by a worm gear, which the finger's load cannot back-drive).
HOLD_STIFFNESS_FACTOR = 20.0


def holding_drive(drive: DriveGains) -> DriveGains:
    """The drive of a joint held by a worm gear: much stiffer and not limited by the
    motor's force (the load cannot back-drive the gear)."""
    return replace(drive, stiffness=drive.stiffness * HOLD_STIFFNESS_FACTOR, force_limit=math.inf)


class HandController:
    """Setpoints and drive targets [rad] of one hand's actuated joints."""

    def __init__(self, hand: HandDescription) -> None:
        self.hand = hand
        self._couplings = [c for c in hand.couplings if not c.in_model]
        self._followers = {c.follower for c in self._couplings}  # moved by their leaders
        self._spec = {j.name: j for j in hand.joints}
        self._commanded: dict[str, float] = dict.fromkeys(hand.joint_names, 0.0)
        self._setpoint: dict[str, float] = dict.fromkeys(hand.joint_names, 0.0)
        self._top_speed = {j.name: j.max_velocity for j in hand.joints}  # [rad/s]
        # [rad/s] each setpoint's speed towards its command (a synchronised hand's: set
        # by `command`)
        self._speed = dict(self._top_speed)
        self._held: dict[str, float] = {}

    def command(self, q_by_joint: Mapping[str, float]) -> None:
        """Command joints [rad]; the others keep their commands. Followers of controller
        couplings follow their leader: a value given for one is replaced by the coupling."""
        for name, value in q_by_joint.items():
            if name not in self._commanded:
                raise UnknownNameError(f"joint of hand {self.hand.name!r}", name, self._commanded)
            if not np.isfinite(value):
                raise GraspframeError(f"hand target for {name!r} is not finite: {value}")
            self._commanded[name] = float(value)
        if self.hand.synchronised_closing:
            self._synchronise()

    def _synchronise(self) -> None:
        """Scale the setpoints' speeds so that every joint reaches its command when the
        slowest one does, at its velocity limit."""
        remaining = {
            n: abs(self._commanded[n] - self._setpoint[n])
            for n in self._commanded
            if n not in self._followers
        }
        duration = max(remaining[n] / self._top_speed[n] for n in remaining)
        for name, distance in remaining.items():
            top = self._top_speed[name]
            self._speed[name] = top if duration <= 0.0 else min(top, distance / duration)

    def update(
        self, dt: float, q: Mapping[str, float], qd: Mapping[str, float]
    ) -> dict[str, float]:
        """Advance the setpoints by `dt` [s] and apply the couplings, given the measured
        positions q [rad] and velocities qd [rad/s]; returns the drive target of every
        actuated joint [rad], within its limits."""
        for name, command in self._commanded.items():
            step = self._speed[name] * dt
            setpoint = self._setpoint[name]
            self._setpoint[name] = setpoint + float(np.clip(command - setpoint, -step, step))
        targets = dict(self._setpoint)
        for c in self._couplings:
            motor = self._setpoint[c.leader]
            if c.breakaway_torque is not None:
                self._update_breakaway(c.leader, c.breakaway_torque, motor, q, qd)
            targets[c.leader] = self._held.get(c.leader, motor)
            targets[c.follower] = c.multiplier * motor + c.offset
        return {
            name: float(np.clip(target, self._spec[name].lower, self._spec[name].upper))
            for name, target in targets.items()
        }

    def _update_breakaway(
        self,
        leader: str,
        breakaway_torque: float,
        motor: float,
        q: Mapping[str, float],
        qd: Mapping[str, float],
    ) -> None:
        """Hold the leader when its drive torque [N m] exceeds the breakaway torque;
        release it when the motor goes back below the held angle."""
        held = self._held.get(leader)
        drive = self.hand.drive
        if held is not None and motor <= held:
            del self._held[leader]  # opening again releases the clutch
        elif held is None:
            torque = drive.stiffness * (motor - q[leader]) - drive.damping * qd[leader]
            if torque > breakaway_torque:
                self._held[leader] = float(q[leader])

    def reset(self, q_measured: Mapping[str, float]) -> None:
        """Make measured positions [rad] the setpoints and commands, release every hold
        (after the backend teleported the joints)."""
        self._setpoint = {name: float(q_measured[name]) for name in self.hand.joint_names}
        self._commanded = dict(self._setpoint)
        self._speed = dict(self._top_speed)
        self._held.clear()

    @property
    def held_leaders(self) -> dict[str, float]:
        """Leader joints currently held by a breakaway, with the angle held [rad]."""
        return dict(self._held)
