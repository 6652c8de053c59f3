"""Jerk-limited joint trajectories (ruckig): planned offline, or stepped online per cycle.

Both kinds are time-optimal under per-joint velocity [rad/s], acceleration [rad/s^2] and
jerk [rad/s^3] limits, with the joints time-synchronised (they start and arrive together).
The community ruckig does not enforce position limits, so both check the planned motion's
position extrema against the joint limits (when known) and refuse a motion that would
leave them. Positions are in [rad], times in [s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import ruckig
from numpy.typing import ArrayLike, NDArray

from graspframe.common.errors import GraspframeError
from graspframe.hal.descriptions import ArmDescription

Vector = NDArray[np.float64]

REST_TOLERANCE = 1e-9  # [rad/s], [rad/s^2] velocity and acceleration counted as zero
_DURATION_ROUNDING = 1e-9  # [s] slack when counting control cycles in a duration
# [rad] round-off allowed when a planned motion's extrema are checked against the position
# limits: a goal exactly on a limit came out up to 5e-15 rad beyond it (measured).
POSITION_ROUNDING = 1e-12


def _vector(values: ArrayLike, dof: int, what: str) -> Vector:
    """A finite float vector of `dof` values, or a one-line GraspframeError."""
    v = np.asarray(values, dtype=float)
    if v.shape != (dof,):
        raise GraspframeError(f"{what} must have {dof} values, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise GraspframeError(f"{what} contains NaN or infinite values: {v.tolist()}")
    return v


def _check_dt(dt: float) -> float:
    try:
        value = float(dt)
    except (TypeError, ValueError):
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise GraspframeError(f"dt (control cycle) must be a finite number > 0 [s], got {dt!r}")
    return value


@dataclass(frozen=True)
class JointLimits:
    """Motion limits of a set of joints, all finite and > 0.

    max_velocity [rad/s], max_acceleration [rad/s^2], max_jerk [rad/s^3]: one per joint.
    lower, upper: [rad] position limits, or None when unknown (then not checked).
    names: joint names, for messages.
    """

    max_velocity: Vector
    max_acceleration: Vector
    max_jerk: Vector
    lower: Vector | None = None
    upper: Vector | None = None
    names: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        dof = np.asarray(self.max_velocity).size
        if dof == 0:
            raise GraspframeError("JointLimits needs at least one joint")
        for what in ("max_velocity", "max_acceleration", "max_jerk"):
            v = _vector(getattr(self, what), dof, f"JointLimits.{what}")
            if not np.all(v > 0):
                raise GraspframeError(f"JointLimits.{what} must be > 0, got {v.tolist()}")
            object.__setattr__(self, what, v)
        if (self.lower is None) != (self.upper is None):
            raise GraspframeError(
                "JointLimits needs both lower and upper position limits, or neither"
            )
        if self.lower is not None and self.upper is not None:
            lower = _vector(self.lower, dof, "JointLimits.lower")
            upper = _vector(self.upper, dof, "JointLimits.upper")
            if not np.all(lower < upper):
                raise GraspframeError(
                    f"JointLimits.lower must be below upper, got {lower.tolist()} and "
                    f"{upper.tolist()}"
                )
            object.__setattr__(self, "lower", lower)
            object.__setattr__(self, "upper", upper)
        names = tuple(self.names) or tuple(f"joint {i}" for i in range(dof))
        if len(names) != dof:
            raise GraspframeError(f"JointLimits.names must have {dof} entries, got {len(names)}")
        object.__setattr__(self, "names", names)

    @property
    def dof(self) -> int:
        return self.max_velocity.size

    @classmethod
    def from_arm(cls, arm: ArmDescription) -> JointLimits:
        """The limits of an arm's JointSpecs (acceleration and jerk must be given)."""
        return cls(
            max_velocity=np.array([j.max_velocity for j in arm.joints]),
            max_acceleration=np.array([j.max_acceleration for j in arm.joints]),
            max_jerk=np.array([j.max_jerk for j in arm.joints]),
            lower=np.array([j.lower for j in arm.joints]),
            upper=np.array([j.upper for j in arm.joints]),
            names=arm.joint_names,
        )

    def scaled(
        self, velocity: float = 1.0, acceleration: float = 1.0, jerk: float = 1.0
    ) -> JointLimits:
        """Limits multiplied by factors in (0, 1], e.g. for a slow approach."""
        for what, factor in (
            ("velocity", velocity),
            ("acceleration", acceleration),
            ("jerk", jerk),
        ):
            if not (math.isfinite(factor) and 0 < factor <= 1):
                raise GraspframeError(f"{what} scale must be in (0, 1], got {factor}")
        return JointLimits(
            self.max_velocity * velocity,
            self.max_acceleration * acceleration,
            self.max_jerk * jerk,
            self.lower,
            self.upper,
            self.names,
        )

    def check_position(self, q: ArrayLike, what: str) -> Vector:
        """q [rad] as a vector; raises if it is outside the position limits."""
        q = _vector(q, self.dof, what)
        if self.lower is not None and self.upper is not None:
            bad = (q < self.lower) | (q > self.upper)
            if np.any(bad):
                outside = [
                    f"{self.names[i]} = {q[i]:.4f} rad not in "
                    f"[{self.lower[i]:.4f}, {self.upper[i]:.4f}]"
                    for i in np.flatnonzero(bad)
                ]
                raise GraspframeError(f"{what} is outside the joint limits: {'; '.join(outside)}")
        return q

    def check_velocity(self, qd: ArrayLike, what: str) -> Vector:
        """qd [rad/s] as a vector; raises if a joint is faster than its limit."""
        qd = _vector(qd, self.dof, what)
        bad = np.abs(qd) > self.max_velocity
        if np.any(bad):
            too_fast = [
                f"{self.names[i]} = {qd[i]:.4f} rad/s, limit {self.max_velocity[i]:.4f}"
                for i in np.flatnonzero(bad)
            ]
            raise GraspframeError(f"{what} exceeds the velocity limits: {'; '.join(too_fast)}")
        return qd

    def apply_to(self, inp: ruckig.InputParameter) -> None:
        inp.max_velocity = self.max_velocity.tolist()
        inp.max_acceleration = self.max_acceleration.tolist()
        inp.max_jerk = self.max_jerk.tolist()

    def check_extrema(self, trajectory: ruckig.Trajectory, what: str) -> None:
        """Raises if a planned motion passes outside the position limits (beyond
        POSITION_ROUNDING)."""
        if self.lower is None or self.upper is None:
            return
        extrema = trajectory.position_extrema
        low = np.array([e.min for e in extrema])
        high = np.array([e.max for e in extrema])
        bad = (low < self.lower - POSITION_ROUNDING) | (high > self.upper + POSITION_ROUNDING)
        if np.any(bad):
            outside = [
                f"{self.names[i]} would reach [{low[i]:.4f}, {high[i]:.4f}] rad, limits "
                f"[{self.lower[i]:.4f}, {self.upper[i]:.4f}]"
                for i in np.flatnonzero(bad)
            ]
            raise GraspframeError(f"{what} leaves the joint limits: {'; '.join(outside)}")


@dataclass(frozen=True)
class JointTrajectory:
    """A trajectory sampled every dt: times (N,) [s], q (N, dof) [rad], qd [rad/s],
    qdd [rad/s^2]; the first sample is the start state, the last the goal state.
    duration [s] = times[-1] (a whole number of control cycles)."""

    times: Vector
    q: Vector
    qd: Vector
    qdd: Vector
    duration: float
    dt: float


def _input(limits: JointLimits) -> ruckig.InputParameter:
    """Ruckig input with the limits, durations rounded up to whole control cycles (so a
    target is reached exactly on a cycle, not between two)."""
    inp = ruckig.InputParameter(limits.dof)
    limits.apply_to(inp)
    inp.duration_discretization = ruckig.DurationDiscretization.Discrete
    return inp


def _raise_on_error(result: ruckig.Result, what: str) -> None:
    if result not in (ruckig.Result.Working, ruckig.Result.Finished):
        raise GraspframeError(f"{what}: ruckig failed with {result.name}")


def plan_joint_trajectory(
    q_start: ArrayLike,
    q_goal: ArrayLike,
    limits: JointLimits,
    dt: float,
    qd_start: ArrayLike | None = None,
) -> JointTrajectory:
    """Time-optimal jerk-limited motion from q_start [rad] (velocity qd_start [rad/s],
    default 0; acceleration 0) to rest at q_goal [rad], sampled every dt [s].

    The duration is rounded up to whole control cycles (ruckig's discrete durations), so
    the last sample is exactly the goal at rest.
    """
    dt = _check_dt(dt)
    q_start = limits.check_position(q_start, "q_start")
    q_goal = limits.check_position(q_goal, "q_goal")
    qd_start = (
        np.zeros(limits.dof) if qd_start is None else limits.check_velocity(qd_start, "qd_start")
    )
    inp = _input(limits)
    inp.current_position = q_start.tolist()
    inp.current_velocity = qd_start.tolist()
    inp.target_position = q_goal.tolist()
    trajectory = ruckig.Trajectory(limits.dof)
    _raise_on_error(ruckig.Ruckig(limits.dof, dt).calculate(inp, trajectory), "joint trajectory")
    limits.check_extrema(trajectory, "the planned joint trajectory")

    duration = float(trajectory.duration)
    cycles = math.ceil(duration / dt - _DURATION_ROUNDING)
    times = dt * np.arange(cycles + 1, dtype=np.float64)
    q, qd, qdd = (np.empty((cycles + 1, limits.dof)) for _ in range(3))
    for k, t in enumerate(times):
        q[k], qd[k], qdd[k] = trajectory.at_time(min(t, duration))
    return JointTrajectory(times, q, qd, qdd, float(times[-1]), dt)


class OnlineTrajectory:
    """A ruckig online generator stepped once per control cycle of dt [s].

    `set_target` replaces the goal at any time; the motion continues smoothly from the
    current setpoint (position, velocity and acceleration). `step` returns the next
    setpoint. `stop` brakes with ruckig's VELOCITY control interface (target velocity and
    acceleration zero): every joint comes to rest within its velocity, acceleration and
    jerk limits, the joints synchronised to stop together in the shortest time the
    slowest one allows; the arm rests wherever braking ends (not at a chosen position).
    Without a target the generator holds its position. A target reached with a non-zero
    velocity is passed through: later steps continue at that velocity (ruckig's
    extrapolation, not checked against the position limits) until the next `set_target`
    or `stop`. Not thread-safe.
    """

    def __init__(self, limits: JointLimits, dt: float, q0: ArrayLike) -> None:
        self.limits = limits
        self.dt = _check_dt(dt)
        self._q = limits.check_position(q0, "q0")
        self._qd = np.zeros(limits.dof)
        self._qdd = np.zeros(limits.dof)
        self._otg = ruckig.Ruckig(limits.dof, self.dt)
        self._check_otg = ruckig.Ruckig(limits.dof, self.dt)  # for the set_target checks
        self._inp = _input(limits)
        self._out = ruckig.OutputParameter(limits.dof)
        self._active = False  # a target or a stop is being followed
        self._finished = True
        self._sync_input()

    def _sync_input(self) -> None:
        self._inp.current_position = self._q.tolist()
        self._inp.current_velocity = self._qd.tolist()
        self._inp.current_acceleration = self._qdd.tolist()

    @property
    def q(self) -> Vector:
        """[rad] the current setpoint position."""
        return self._q.copy()

    @property
    def qd(self) -> Vector:
        """[rad/s] the current setpoint velocity."""
        return self._qd.copy()

    @property
    def qdd(self) -> Vector:
        """[rad/s^2] the current setpoint acceleration."""
        return self._qdd.copy()

    @property
    def at_rest(self) -> bool:
        """Velocity and acceleration are zero (within REST_TOLERANCE)."""
        return bool(
            np.all(np.abs(self._qd) <= REST_TOLERANCE)
            and np.all(np.abs(self._qdd) <= REST_TOLERANCE)
        )

    @property
    def finished(self) -> bool:
        """The last target (or stop) has been reached."""
        return self._finished

    def set_target(self, q_goal: ArrayLike, qd_goal: ArrayLike | None = None) -> None:
        """Move to q_goal [rad], arriving with velocity qd_goal [rad/s] (default 0).

        Raises (and keeps the previous target) when the goal is outside the joint limits
        or the motion from the current state would pass outside them.
        """
        q_goal = self.limits.check_position(q_goal, "q_goal")
        qd_goal = (
            np.zeros(self.limits.dof)
            if qd_goal is None
            else self.limits.check_velocity(qd_goal, "qd_goal")
        )
        inp = _input(self.limits)
        inp.current_position = self._q.tolist()
        inp.current_velocity = self._qd.tolist()
        inp.current_acceleration = self._qdd.tolist()
        inp.target_position = q_goal.tolist()
        inp.target_velocity = qd_goal.tolist()
        trajectory = ruckig.Trajectory(self.limits.dof)
        _raise_on_error(self._check_otg.calculate(inp, trajectory), "online target")
        self.limits.check_extrema(trajectory, "the motion to the new target")

        self._inp.control_interface = ruckig.ControlInterface.Position
        self._inp.target_position = q_goal.tolist()
        self._inp.target_velocity = qd_goal.tolist()
        self._inp.target_acceleration = [0.0] * self.limits.dof
        self._active, self._finished = True, False

    def stop(self) -> None:
        """Brake to rest as fast as the limits allow (velocity interface, see the class)."""
        self._inp.control_interface = ruckig.ControlInterface.Velocity
        self._inp.target_velocity = [0.0] * self.limits.dof
        self._inp.target_acceleration = [0.0] * self.limits.dof
        self._active, self._finished = True, self.at_rest

    def step(self) -> tuple[Vector, Vector, Vector]:
        """Advance one control cycle: the next setpoint (q [rad], qd [rad/s], qdd [rad/s^2])."""
        if self._active and not (self._finished and self.at_rest):
            result = self._otg.update(self._inp, self._out)
            _raise_on_error(result, "online trajectory step")
            self._out.pass_to_input(self._inp)
            self._q = np.array(self._out.new_position)
            self._qd = np.array(self._out.new_velocity)
            self._qdd = np.array(self._out.new_acceleration)
            # Ruckig says Finished one cycle after the one that lands on the target (its
            # durations are whole cycles here); count the landing cycle as the finish.
            self._finished = result == ruckig.Result.Finished or (
                self._out.time >= self._out.trajectory.duration - _DURATION_ROUNDING
            )
            if self._finished and self.at_rest:
                # Round-off (~1e-16) is left in a state that is at rest: make it exact.
                self._qd[:] = 0.0
                self._qdd[:] = 0.0
                self._sync_input()
        return self.q, self.qd, self.qdd
