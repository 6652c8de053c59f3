"""Jerk-limited joint trajectories (graspframe.motion.trajectory) on every registered arm.

Limits are checked on the sampled setpoints: velocity and acceleration directly, jerk as
the finite difference of consecutive accelerations over one control cycle (the mean jerk
over that cycle, so it is bounded by the jerk limit exactly, not only approximately).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from graspframe.common.errors import GraspframeError
from graspframe.hal.descriptions import JointSpec
from graspframe.motion import JointLimits, OnlineTrajectory, plan_joint_trajectory
from graspframe.plugin_system.registry import default_registry

REGISTRY = default_registry()
ARMS = REGISTRY.names("arm")
DT = 0.001  # [s] a 1 kHz control cycle
SEED = 7
# Relative slack on every limit: ruckig computes profiles in double precision and the
# samples carry round-off of ~1e-15 relative; 1e-9 leaves room for that and nothing else.
REL_TOL = 1e-9
# Jerk from a finite difference of accelerations: the round-off of qdd (~1e-14 rad/s^2)
# divided by dt (1e-3 s) is ~1e-11 rad/s^3; the limits are ~100 rad/s^3.
JERK_ABS_TOL = 1e-6  # [rad/s^3]
# [rad], [rad/s], [rad/s^2]: a reached state equals the requested one to round-off.
STATE_TOL = 1e-9
MARGIN = 0.05  # [rad] random positions are drawn this far inside the position limits
# [rad] a goal exactly on a limit is reached to round-off (the module allows 1e-12 rad).
POSITION_TOL = 1e-12


@pytest.fixture(scope="module", params=ARMS)
def limits(request) -> JointLimits:
    return JointLimits.from_arm(REGISTRY.get_arm(request.param))


def _random_q(limits: JointLimits, rng: np.random.Generator) -> np.ndarray:
    return rng.uniform(limits.lower + MARGIN, limits.upper - MARGIN)


def assert_within_limits(limits: JointLimits, q, qd, qdd, dt: float = DT) -> None:
    """Sampled setpoints (N, dof) never exceed position, velocity, acceleration, jerk."""
    q, qd, qdd = (np.atleast_2d(a) for a in (q, qd, qdd))
    assert np.all(q >= limits.lower - POSITION_TOL) and np.all(q <= limits.upper + POSITION_TOL)
    assert np.all(np.abs(qd) <= limits.max_velocity * (1 + REL_TOL))
    assert np.all(np.abs(qdd) <= limits.max_acceleration * (1 + REL_TOL))
    jerk = np.abs(np.diff(qdd, axis=0)) / dt
    excess = jerk - (limits.max_jerk * (1 + REL_TOL) + JERK_ABS_TOL)
    assert np.all(excess <= 0), f"jerk above the limit by up to {excess.max():.3g} rad/s^3"


def run_online(generator: OnlineTrajectory, max_steps: int, history: list | None = None):
    """Step until finished; returns the stacked (q, qd, qdd) including the start state."""
    samples = [(generator.q, generator.qd, generator.qdd)] if history is None else history
    for _ in range(max_steps):
        samples.append(generator.step())
        if generator.finished:
            break
    else:
        raise AssertionError(f"not finished after {max_steps} steps")
    return tuple(np.array(column) for column in zip(*samples, strict=True))


def braking_time_bound(limits: JointLimits) -> float:
    """[s] an upper bound on the time to rest from any state within the limits: bring
    the acceleration to zero (a/j), then brake from at most v_max with a trapezoidal
    acceleration profile (v/a + a/j); the slowest joint decides."""
    v, a, j = limits.max_velocity, limits.max_acceleration, limits.max_jerk
    return float(np.max(v / a + 2 * a / j))


# -- offline ------------------------------------------------------------------------------


def test_from_arm_reads_the_joint_specs():
    for name in ARMS:
        arm = REGISTRY.get_arm(name)
        limits = JointLimits.from_arm(arm)
        assert limits.dof == arm.dof and limits.names == arm.joint_names
        assert limits.max_jerk.tolist() == [j.max_jerk for j in arm.joints]
        assert limits.lower.tolist() == [j.lower for j in arm.joints]


def test_offline_trajectories_respect_limits_and_end_states(limits):
    rng = np.random.default_rng(SEED)
    for k in range(8):
        q_start, q_goal = _random_q(limits, rng), _random_q(limits, rng)
        # Half of them start moving (up to half speed) towards the middle of the range.
        qd_start = None
        if k % 2:
            middle = (limits.lower + limits.upper) / 2
            qd_start = 0.5 * limits.max_velocity * rng.uniform(0, 1) * np.sign(middle - q_start)
        trajectory = plan_joint_trajectory(q_start, q_goal, limits, DT, qd_start)

        assert_within_limits(limits, trajectory.q, trajectory.qd, trajectory.qdd)
        np.testing.assert_allclose(trajectory.q[0], q_start, atol=STATE_TOL)
        np.testing.assert_allclose(
            trajectory.qd[0], np.zeros(limits.dof) if qd_start is None else qd_start, atol=STATE_TOL
        )
        np.testing.assert_allclose(trajectory.qdd[0], 0.0, atol=STATE_TOL)
        np.testing.assert_allclose(trajectory.q[-1], q_goal, atol=STATE_TOL)
        np.testing.assert_allclose(trajectory.qd[-1], 0.0, atol=STATE_TOL)
        np.testing.assert_allclose(trajectory.qdd[-1], 0.0, atol=STATE_TOL)
        # Sampled every dt, ending exactly on a control cycle.
        np.testing.assert_allclose(np.diff(trajectory.times), DT, rtol=1e-9)
        assert trajectory.duration == pytest.approx(trajectory.times[-1])
        # No motion can be faster than the furthest-moving joint at full speed throughout.
        if qd_start is None:
            assert trajectory.duration >= np.max(np.abs(q_goal - q_start) / limits.max_velocity)


def test_offline_zero_motion_is_one_sample(limits):
    q = (limits.lower + limits.upper) / 2
    trajectory = plan_joint_trajectory(q, q, limits, DT)
    assert trajectory.duration == 0.0 and trajectory.q.shape == (1, limits.dof)


# -- online -------------------------------------------------------------------------------


def test_online_reaches_targets_within_limits(limits):
    rng = np.random.default_rng(SEED + 1)
    q0 = _random_q(limits, rng)
    generator = OnlineTrajectory(limits, DT, q0)
    assert generator.at_rest and generator.finished
    for _ in range(4):
        q_goal = _random_q(limits, rng)
        generator.set_target(q_goal)
        assert not generator.finished
        q, qd, qdd = run_online(generator, max_steps=20_000)
        assert_within_limits(limits, q, qd, qdd)
        np.testing.assert_allclose(generator.q, q_goal, atol=STATE_TOL)
        assert generator.at_rest
        # Matches the offline plan of the same motion, sample for sample.
        offline = plan_joint_trajectory(q[0], q_goal, limits, DT)
        np.testing.assert_allclose(q, offline.q, atol=1e-9)


def test_online_target_change_mid_motion_stays_within_limits(limits):
    rng = np.random.default_rng(SEED + 2)
    for _ in range(4):
        generator = OnlineTrajectory(limits, DT, _random_q(limits, rng))
        generator.set_target(_random_q(limits, rng))
        history = [(generator.q, generator.qd, generator.qdd)]
        for _ in range(int(rng.integers(50, 300))):  # 50-300 ms into the motion
            history.append(generator.step())
        assert not generator.at_rest  # the change happens while moving
        q_new = _random_q(limits, rng)
        generator.set_target(q_new)
        q, qd, qdd = run_online(generator, max_steps=20_000, history=history)
        assert_within_limits(limits, q, qd, qdd)
        np.testing.assert_allclose(generator.q, q_new, atol=STATE_TOL)


def test_stop_brings_motion_to_rest_within_limits_in_bounded_time(limits):
    rng = np.random.default_rng(SEED + 3)
    bound = braking_time_bound(limits)
    for _ in range(4):
        start = _random_q(limits, rng)
        # The furthest goal in the joint ranges, so the joints reach high speeds.
        goal = np.where(start < (limits.lower + limits.upper) / 2, limits.upper, limits.lower)
        generator = OnlineTrajectory(limits, DT, start)
        generator.set_target(goal)
        history = [(generator.q, generator.qd, generator.qdd)]
        for _ in range(int(rng.integers(100, 400))):
            history.append(generator.step())
        assert not generator.at_rest
        stop_index = len(history)
        generator.stop()
        q, qd, qdd = run_online(generator, max_steps=20_000, history=history)
        assert_within_limits(limits, q, qd, qdd)
        assert generator.at_rest
        braking_time = (len(q) - stop_index) * DT
        assert braking_time <= bound + DT, (braking_time, bound)
        # At rest it stays put.
        resting = generator.q
        for _ in range(10):
            q_next, qd_next, _ = generator.step()
            np.testing.assert_array_equal(q_next, resting)
            np.testing.assert_array_equal(qd_next, 0.0)


def test_holds_without_target(limits):
    q0 = (limits.lower + limits.upper) / 2
    generator = OnlineTrajectory(limits, DT, q0)
    for _ in range(5):
        q, qd, qdd = generator.step()
        np.testing.assert_array_equal(q, q0)
        assert not np.any(qd) and not np.any(qdd)


# -- inputs -------------------------------------------------------------------------------

SMALL = JointLimits(
    max_velocity=np.array([2.0]),
    max_acceleration=np.array([2.0]),
    max_jerk=np.array([10.0]),
    lower=np.array([-1.0]),
    upper=np.array([1.0]),
    names=("j",),
)


def test_set_target_refuses_a_motion_that_would_leave_the_limits():
    generator = OnlineTrajectory(SMALL, DT, [-0.5])
    generator.set_target([0.5], qd_goal=[2.0])  # pass through 0.5 rad at full speed
    run_online(generator, max_steps=10_000)
    # Braking from 2 rad/s takes ~1.2 rad: a goal at 0.9 rad would overshoot 1 rad.
    with pytest.raises(GraspframeError, match="leaves the joint limits"):
        generator.set_target([0.9])
    generator.stop()  # still possible; the previous target was kept until now
    run_online(generator, max_steps=10_000)
    assert generator.at_rest


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"max_velocity": [1.0, -1.0]}, "max_velocity must be > 0"),
        ({"max_acceleration": [1.0, 0.0]}, "max_acceleration must be > 0"),
        ({"max_jerk": [1.0, math.inf]}, "NaN or infinite"),
        ({"max_jerk": [1.0]}, "must have 2 values"),
        ({"lower": [0.0, 0.0]}, "both lower and upper"),
        ({"lower": [0.0, 1.0], "upper": [1.0, 0.0]}, "below upper"),
    ],
)
def test_bad_limits_raise(kwargs, match):
    values = {"max_velocity": [1.0, 1.0], "max_acceleration": [1.0, 1.0], "max_jerk": [1.0, 1.0]}
    values |= kwargs
    with pytest.raises(GraspframeError, match=match) as raised:
        JointLimits(**{k: np.asarray(v) for k, v in values.items()})
    assert "\n" not in str(raised.value)


def test_from_arm_refuses_infinite_jerk():
    arm = REGISTRY.get_arm(ARMS[0])
    spec = arm.joints[0]
    unlimited = JointSpec(spec.name, spec.lower, spec.upper, spec.max_velocity, 1.0)
    broken = type(arm)(**{**arm.__dict__, "joints": (unlimited, *arm.joints[1:])})
    with pytest.raises(GraspframeError, match="infinite"):
        JointLimits.from_arm(broken)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: plan_joint_trajectory([0.0, 0.0], [0.1], SMALL, DT), "must have 1 values"),
        (lambda: plan_joint_trajectory([0.0], [math.nan], SMALL, DT), "NaN"),
        (lambda: plan_joint_trajectory([0.0], [1.5], SMALL, DT), "outside the joint limits"),
        (lambda: plan_joint_trajectory([0.0], [0.5], SMALL, 0.0), "dt"),
        (lambda: plan_joint_trajectory([0.0], [0.5], SMALL, -1e-3), "dt"),
        (lambda: plan_joint_trajectory([0.0], [0.5], SMALL, DT, [3.0]), "velocity limits"),
        (lambda: OnlineTrajectory(SMALL, math.inf, [0.0]), "dt"),
        (lambda: OnlineTrajectory(SMALL, DT, [2.0]), "outside the joint limits"),
        (lambda: OnlineTrajectory(SMALL, DT, [0.0]).set_target([0.1, 0.2]), "must have 1"),
        (lambda: OnlineTrajectory(SMALL, DT, [0.0]).set_target([0.1], [math.inf]), "NaN"),
        (lambda: SMALL.scaled(velocity=0.0), "scale"),
    ],
)
def test_bad_inputs_raise(call, match):
    with pytest.raises(GraspframeError, match=match) as raised:
        call()
    assert "\n" not in str(raised.value)
