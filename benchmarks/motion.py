"""Motion-layer timings: IK solve (placo), ruckig online step and offline plan.

Run: python benchmarks/motion.py [--arm kuka] [--hand barrett]

Prints its figures; asserts nothing. Each figure is one function returning a dict of
named numbers (units in the names); `main` runs the sections in `SECTIONS` in turn, so a
further section (e.g. a SAPIEN real-time factor) is one more function appended there.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np

from graspframe.common.defaults import DEFAULT_ARM, SCENE_OBJECT_XY
from graspframe.motion import IkSolver, JointLimits, OnlineTrajectory, plan_joint_trajectory
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.mounting import mount

SEED = 0
IK_TARGETS = 200
SAMPLE_MARGIN = 0.1  # [rad] targets come from configurations this far inside the limits
WARM_STEP = 0.02  # [rad] per-joint standard deviation between consecutive warm targets
CONTROL_DT = 0.001  # [s] a 1 kHz control cycle
ONLINE_MOTIONS = 20
OFFLINE_PLANS = 200


def _stats(values, scale: float, unit: str, name: str) -> dict[str, float]:
    values = np.asarray(values, dtype=float) * scale
    return {
        f"{name} median [{unit}]": float(np.median(values)),
        f"{name} p95 [{unit}]": float(np.percentile(values, 95)),
        f"{name} max [{unit}]": float(np.max(values)),
    }


def ik_solve_times(arm: str, hand: str) -> dict[str, float]:
    """IK over IK_TARGETS reachable palm targets, cold (from home_q) and warm (a random
    walk in joint space, each target seeded with the previous solution)."""
    registry = default_registry()
    started = time.perf_counter()
    solver = IkSolver(mount(registry.get_arm(arm), registry.get_hand(hand)))
    build_s = time.perf_counter() - started
    rng = np.random.default_rng(SEED)
    low, high = solver.lower + SAMPLE_MARGIN, solver.upper - SAMPLE_MARGIN

    cold_s, cold_iterations, cold_attempts = [], [], []
    for _ in range(IK_TARGETS):
        T_target = solver.forward_palm(rng.uniform(low, high))
        started = time.perf_counter()
        solution = solver.solve(T_target)
        cold_s.append(time.perf_counter() - started)
        cold_iterations.append(solution.iterations)
        cold_attempts.append(solution.attempts)

    warm_s, warm_iterations = [], []
    q_walk = solver.home_q.copy()
    q_seed = solver.home_q
    for _ in range(IK_TARGETS):
        q_walk = np.clip(q_walk + rng.normal(0.0, WARM_STEP, q_walk.size), low, high)
        T_target = solver.forward_palm(q_walk)
        started = time.perf_counter()
        solution = solver.solve(T_target, q_seed=q_seed)
        warm_s.append(time.perf_counter() - started)
        warm_iterations.append(solution.iterations)
        q_seed = solution.q_arm

    return {
        "solver build [ms]": 1e3 * build_s,
        **_stats(cold_s, 1e3, "ms", "cold solve"),
        "cold iterations median": float(np.median(cold_iterations)),
        "cold iterations p95": float(np.percentile(cold_iterations, 95)),
        "cold attempts mean": float(np.mean(cold_attempts)),
        **_stats(warm_s, 1e3, "ms", "warm solve"),
        "warm iterations median": float(np.median(warm_iterations)),
        "warm iterations p95": float(np.percentile(warm_iterations, 95)),
    }


def online_step_times(arm: str, hand: str) -> dict[str, float]:
    """OnlineTrajectory.step per control cycle and set_target (which checks the motion
    against the position limits) over ONLINE_MOTIONS random motions."""
    limits = JointLimits.from_arm(default_registry().get_arm(arm))
    rng = np.random.default_rng(SEED)
    low, high = limits.lower + SAMPLE_MARGIN, limits.upper - SAMPLE_MARGIN
    generator = OnlineTrajectory(limits, CONTROL_DT, rng.uniform(low, high))
    step_s, target_s, cycles = [], [], 0
    for _ in range(ONLINE_MOTIONS):
        started = time.perf_counter()
        generator.set_target(rng.uniform(low, high))
        target_s.append(time.perf_counter() - started)
        while not generator.finished:
            started = time.perf_counter()
            generator.step()
            step_s.append(time.perf_counter() - started)
            cycles += 1
    return {
        **_stats(step_s, 1e6, "us", "online step"),
        **_stats(target_s, 1e6, "us", "set_target"),
        "control cycles": float(cycles),
    }


def offline_plan_times(arm: str, hand: str) -> dict[str, float]:
    """plan_joint_trajectory between random configurations, sampled at CONTROL_DT."""
    limits = JointLimits.from_arm(default_registry().get_arm(arm))
    rng = np.random.default_rng(SEED)
    low, high = limits.lower + SAMPLE_MARGIN, limits.upper - SAMPLE_MARGIN
    plan_s, durations = [], []
    for _ in range(OFFLINE_PLANS):
        q_start, q_goal = rng.uniform(low, high), rng.uniform(low, high)
        started = time.perf_counter()
        trajectory = plan_joint_trajectory(q_start, q_goal, limits, CONTROL_DT)
        plan_s.append(time.perf_counter() - started)
        durations.append(trajectory.duration)
    return {
        **_stats(plan_s, 1e3, "ms", "plan incl. sampling"),
        "trajectory duration median [s]": float(np.median(durations)),
    }


# Title, function(arm, hand) -> figures. Append further sections here.
def simulation_real_time_factor(arm: str, hand: str) -> dict[str, float]:
    """A 5 s approach-and-close in SAPIEN: simulated seconds per wall-clock second."""
    from graspframe_sapien.backend import SapienBackend

    from graspframe.common.transforms import R_from_rpy, make_T
    from graspframe.hal import WorldConfig
    from graspframe.motion.arm_motion import ArmMotion
    from graspframe.plugin_system.registry import default_registry

    registry = default_registry()
    arm_d, hand_d = registry.get_arm(arm), registry.get_hand(hand)
    can = registry.get_object("large_cylinder")
    T_world_object = make_T(p=[*SCENE_OBJECT_XY, can.half_height])
    started = time.perf_counter()
    robot = mount(arm_d, hand_d)
    world = SapienBackend().create_world(
        WorldConfig(hand=hand_d, robot=robot, object=can, T_world_object=T_world_object)
    )
    build = time.perf_counter() - started
    motion = ArmMotion(world, robot, np.eye(4))
    R_palm_down = R_from_rpy(np.pi, 0.0, 0.0)
    started = time.perf_counter()
    sim_start = world.time
    motion.move_palm_to(make_T(R_palm_down, [*SCENE_OBJECT_XY, 0.30]))
    motion.move_palm_linear(np.array([0.0, 0.0, -1.0]), 0.12, 0.05)  # stops at contact
    world.hand.set_joint_targets(next(iter(hand_d.preshapes.values())).closed_q)
    remaining = max(0.0, 5.0 - (world.time - sim_start))
    world.step(round(remaining / world.timestep))
    wall = time.perf_counter() - started
    simulated = world.time - sim_start
    return {
        "world build [s]": build,
        "simulated [s]": simulated,
        "wall [s]": wall,
        "real-time factor [-]": simulated / wall,
    }


SECTIONS: list[tuple[str, Callable[[str, str], dict[str, float]]]] = [
    ("IK solve (placo), palm targets", ik_solve_times),
    ("ruckig online, per control cycle", online_step_times),
    ("ruckig offline plan", offline_plan_times),
    ("SAPIEN approach and close (5 s simulated)", simulation_real_time_factor),
]


def print_figures(title: str, figures: dict[str, float]) -> None:
    print(f"\n{title}")
    width = max(len(name) for name in figures)
    for name, value in figures.items():
        print(f"  {name:<{width}}  {value:10.3f}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arm", default=DEFAULT_ARM)
    parser.add_argument("--hand", default="barrett")
    args = parser.parse_args(argv)
    print(f"motion benchmark: arm {args.arm}, hand {args.hand}, control dt {CONTROL_DT} s")
    for title, section in SECTIONS:
        print_figures(title, section(args.arm, args.hand))


if __name__ == "__main__":
    main()
