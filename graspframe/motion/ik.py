"""Inverse kinematics of the palm frame of a hand mounted on an arm (placo on Pinocchio).

The model is the combined hand-on-arm URDF of a `MountedRobot`. Only the arm joints move:
every hand joint (and every <mimic> follower) is masked at the value the caller gives.
Each solver step is one placo QP: a soft frame task on the palm frame, the arm's joint
limits as HARD inequality constraints and a per-step trust region of `max_step` [rad] per
joint (placo's velocity-limit constraint with every limit 1 rad/s and dt = max_step),
which keeps the Gauss-Newton steps from jumping across the workspace onto a limit.

Steps repeat until the palm is within (`position_tolerance`, `orientation_tolerance`) of
the target, the error stalls or the step vanishes (stuck on a limit), or `max_iterations`
is reached. The seed goes first, then the arm's home configuration, then `restarts`
further seeds drawn by a numpy Generator seeded with `seed` afresh for every call (so a
solve does not depend on earlier calls): two perturbations of the seed, then uniform
samples within the limits (they cover the configuration space better than perturbations:
fewer false "unreachable" verdicts were measured). The first attempt within tolerance
wins; otherwise the best attempt is accepted if it is within the acceptance thresholds
(ACCEPT_POSITION_ERROR, ACCEPT_ORIENTATION_ERROR), else `UnreachableError`. A returned
solution is checked against the arm's joint limits exactly (never clipped).

Not modelled: collisions (self, table, object); a solution may put the arm through them.

An `IkSolver` builds the placo robot and solver once; it keeps state between calls and is
not thread-safe (one per thread).
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from graspframe.common.errors import GraspframeError, MotionError
from graspframe.common.transforms import as_pose, inv_T, rpy_from_R
from graspframe.hal.mounted_robot import MountedRobot

POSITION_TOLERANCE = 1e-4  # [m] iterate until the palm position error is below this
ORIENTATION_TOLERANCE = 1e-3  # [rad] ... and the palm orientation error below this
ACCEPT_POSITION_ERROR = 1e-3  # [m] a solution further than 1 mm is unreachable
ACCEPT_ORIENTATION_ERROR = math.radians(1.0)  # [rad] ... or turned by more than 1 deg
MAX_ITERATIONS = 100  # solver steps per attempt
# Attempts after the seed and home_q. Measured on kuka+barrett, 3000 targets from uniform
# configurations 0.1 rad inside the limits: 24 false "unreachable" with 12 restarts, 3
# with 20, 0 with 40 (also 0 at 0.02 rad inside); a truly unreachable target costs ~15 ms.
RESTARTS = 40
PERTURBED_SEEDS = 2  # the first restarts perturb the seed; the others sample uniformly
MAX_STEP = 0.4  # [rad] largest change of one arm joint in one solver step
SEED_PERTURBATION = 0.3  # [rad] standard deviation of the perturbed-seed restarts
# [rad] the solver's hard limits sit this far inside the description's, so that rounding
# in the QP (seen: 4e-16 rad) never places a solution outside; the check below is exact.
LIMIT_MARGIN = 1e-9
# A stalled attempt is abandoned: after STALL_WINDOW steps, the error (position [m] plus
# STALL_LENGTH [m/rad] x orientation [rad]) must have dropped below STALL_RATIO of its value
# STALL_WINDOW steps earlier.
STALL_WINDOW = 10
STALL_RATIO = 0.9
STALL_LENGTH = 0.1  # [m/rad]
# [rad] an attempt whose step moves no arm joint by more than this is stuck (typically
# pressed against a joint limit by a target on the far side of it) and is abandoned.
STUCK_STEP = 1e-10
_WIDE_LIMIT = 1e3  # [rad] limits given to the masked hand joints (they never move)


class UnreachableError(MotionError):
    """No arm configuration within the joint limits puts the palm on the target."""


class IkLimitError(GraspframeError):
    """The solver returned a configuration outside the arm's joint limits (a bug)."""


@dataclass(frozen=True)
class IkSolution:
    """A palm pose reached by the arm.

    q_arm: [rad] arm joint values in `arm.joint_names` order, inside the joint limits.
    position_error: [m] distance from the palm frame origin to the target's.
    orientation_error: [rad] angle of the rotation from the palm frame to the target's.
    iterations: solver steps over all attempts.
    attempts: seeds tried (1 = the seed converged).
    """

    q_arm: NDArray[np.float64]
    position_error: float
    orientation_error: float
    iterations: int
    attempts: int


def describe_pose(T_base_palm: NDArray[np.float64]) -> str:
    """One-line "position [mm], rpy [deg]" of a pose in the arm base frame."""
    p_mm = 1000.0 * T_base_palm[:3, 3]
    rpy_deg = np.degrees(rpy_from_R(T_base_palm[:3, :3]))
    return (
        f"p_base = ({p_mm[0]:.1f}, {p_mm[1]:.1f}, {p_mm[2]:.1f}) mm, "
        f"rpy = ({rpy_deg[0]:.1f}, {rpy_deg[1]:.1f}, {rpy_deg[2]:.1f}) deg"
    )


class IkSolver:
    """Palm-pose IK for one `MountedRobot`; see the module docstring for the method.

    position_tolerance [m], orientation_tolerance [rad]: convergence thresholds.
    max_iterations: solver steps per attempt; restarts: attempts after seed and home_q.
    max_step: [rad] trust region per joint and step. seed: of the restart Generator.
    """

    def __init__(
        self,
        robot: MountedRobot,
        *,
        position_tolerance: float = POSITION_TOLERANCE,
        orientation_tolerance: float = ORIENTATION_TOLERANCE,
        max_iterations: int = MAX_ITERATIONS,
        restarts: int = RESTARTS,
        max_step: float = MAX_STEP,
        seed: int = 0,
    ) -> None:
        import placo

        for name, value in (
            ("position_tolerance", position_tolerance),
            ("orientation_tolerance", orientation_tolerance),
            ("max_step", max_step),
        ):
            if not (math.isfinite(value) and value > 0):
                raise GraspframeError(f"IkSolver {name} must be finite and > 0, got {value}")
        if max_iterations < 1 or restarts < 0:
            raise GraspframeError(
                f"IkSolver needs max_iterations >= 1 and restarts >= 0, "
                f"got {max_iterations} and {restarts}"
            )
        self.robot = robot
        self.arm = robot.arm
        self.hand = robot.hand
        self.position_tolerance = float(position_tolerance)
        self.orientation_tolerance = float(orientation_tolerance)
        self.max_iterations = int(max_iterations)
        self.restarts = int(restarts)
        self.seed = int(seed)

        self.lower = np.array([j.lower for j in self.arm.joints])  # [rad]
        self.upper = np.array([j.upper for j in self.arm.joints])  # [rad]
        self.home_q = self._check_q_arm(self.arm.home_q, "arm.home_q")

        # placo reads the model text; the folder is only where it would look for meshes,
        # which the text names by absolute path.
        self._model = placo.RobotWrapper(
            str(Path.cwd()), placo.Flags.ignore_collisions, robot.model.text
        )
        model_joints = set(self._model.joint_names())
        missing = [n for n in self.arm.joint_names if n not in model_joints]
        if missing:
            raise GraspframeError(
                f"{robot.name}: arm joints {', '.join(missing)} are not in its model"
            )
        self._hand_joints = [n for n in self._model.joint_names() if n not in self.arm.joint_names]
        self._arm_index = np.array([self._model.get_joint_offset(n) for n in self.arm.joint_names])
        self._arm_v_index = np.array(
            [self._model.get_joint_v_offset(n) for n in self.arm.joint_names]
        )

        self._solver = placo.KinematicsSolver(self._model)
        self._solver.mask_fbase(True)
        self._solver.enable_joint_limits(True)
        self._solver.enable_velocity_limits(True)
        self._solver.dt = float(max_step)  # step bound = dt x velocity limit (1 rad/s)
        for spec in self.arm.joints:
            self._model.set_joint_limits(
                spec.name, spec.lower + LIMIT_MARGIN, spec.upper - LIMIT_MARGIN
            )
            self._model.set_velocity_limit(spec.name, 1.0)
        for name in self._hand_joints:
            self._solver.mask_dof(name)
            self._model.set_joint_limits(name, -_WIDE_LIMIT, _WIDE_LIMIT)
            self._model.set_velocity_limit(name, 1.0)
        self._task = self._solver.add_frame_task(self.hand.palm_frame, np.eye(4))
        self._task.configure("palm", "soft", 1.0, 1.0)
        self._position_task = self._task.position()
        self._orientation_task = self._task.orientation()

        # World of the placo model = the URDF root; the arm base is fixed in it.
        self._model.update_kinematics()
        self._T_world_base = self._model.get_T_world_frame(self.arm.base_link).copy()
        self._T_base_world = inv_T(self._T_world_base)
        self._q_hand_default = self._full_hand_q(None)

    # -- inputs -------------------------------------------------------------------------

    def _check_q_arm(self, q_arm: ArrayLike, what: str) -> NDArray[np.float64]:
        q = np.asarray(q_arm, dtype=float)
        if q.shape != (self.arm.dof,):
            raise GraspframeError(
                f"{what} must have {self.arm.dof} values ({', '.join(self.arm.joint_names)}), "
                f"got shape {q.shape}"
            )
        if not np.all(np.isfinite(q)):
            raise GraspframeError(f"{what} contains NaN or infinite values: {q.tolist()}")
        return q

    def _full_hand_q(self, q_hand: Mapping[str, float] | None) -> dict[str, float]:
        """Every hand joint of the model [rad]: given values, else the value nearest 0
        within the joint's limits, plus the <mimic> followers."""
        q_by_joint = {j.name: min(max(0.0, j.lower), j.upper) for j in self.hand.joints}
        for name, value in (q_hand or {}).items():
            spec = self.hand.joint(name)  # unknown names raise, listing the known ones
            if not (math.isfinite(value) and spec.contains(value)):
                raise GraspframeError(
                    f"hand joint {name!r} = {value} rad is outside its limits "
                    f"[{spec.lower:.4f}, {spec.upper:.4f}] rad"
                )
            q_by_joint[name] = float(value)
        full = self.hand.with_model_followers(q_by_joint)
        return {name: full.get(name, 0.0) for name in self._hand_joints}

    # -- model state --------------------------------------------------------------------

    def _set_state(self, q_arm: NDArray[np.float64], q_hand: Mapping[str, float]) -> None:
        for name, value in q_hand.items():
            self._model.set_joint(name, value)
        q = self._model.state.q
        q[self._arm_index] = q_arm
        self._model.state.q = q
        self._model.update_kinematics()

    def _q_arm(self) -> NDArray[np.float64]:
        return self._model.state.q[self._arm_index].copy()

    def hand_q_in_model(self) -> dict[str, float]:
        """[rad] every hand joint (followers included) as the solver's model holds it now,
        for checks that IK left the hand alone."""
        return {name: float(self._model.get_joint(name)) for name in self._hand_joints}

    def forward_palm(
        self, q_arm: ArrayLike, q_hand: Mapping[str, float] | None = None
    ) -> NDArray[np.float64]:
        """T_base_palm (4x4) for arm joints q_arm [rad] and hand joints q_hand [rad]."""
        q_arm = self._check_q_arm(q_arm, "q_arm")
        self._set_state(q_arm, self._full_hand_q(q_hand))
        return self._T_base_world @ self._model.get_T_world_frame(self.hand.palm_frame)

    # -- solving ------------------------------------------------------------------------

    def _seeds(self, q_seed: NDArray[np.float64]) -> Iterator[NDArray[np.float64]]:
        """The seed, home_q, then `restarts` deterministic seeds (clamped into the limits):
        PERTURBED_SEEDS perturbations of the seed, then uniform samples within the limits."""
        yield q_seed
        if not np.allclose(q_seed, self.home_q):
            yield self.home_q
        rng = np.random.default_rng(self.seed)
        for k in range(self.restarts):
            if k < PERTURBED_SEEDS:
                q = q_seed + rng.normal(0.0, SEED_PERTURBATION, self.arm.dof)
            else:
                q = rng.uniform(self.lower, self.upper)
            yield np.clip(q, self.lower, self.upper)

    def _errors(self) -> tuple[float, float]:
        """Current palm position error [m] and orientation error [rad] to the task target."""
        self._position_task.update()
        self._orientation_task.update()
        return self._position_task.error_norm(), self._orientation_task.error_norm()

    def _descend(
        self, q_start: NDArray[np.float64], q_hand: Mapping[str, float]
    ) -> tuple[NDArray[np.float64], float, float, int]:
        """One attempt from q_start: (q_arm, position error, orientation error, steps)."""
        self._set_state(q_start, q_hand)
        history: list[float] = []
        steps = 0
        while True:
            position_error, orientation_error = self._errors()
            if (
                position_error < self.position_tolerance
                and orientation_error < self.orientation_tolerance
            ) or steps >= self.max_iterations:
                break
            history.append(position_error + STALL_LENGTH * orientation_error)
            if (
                len(history) > STALL_WINDOW
                and history[-1] > STALL_RATIO * history[-1 - STALL_WINDOW]
            ):
                break
            dq = self._solver.solve(True)
            self._model.update_kinematics()
            steps += 1
            if np.max(np.abs(dq[self._arm_v_index])) < STUCK_STEP:
                position_error, orientation_error = self._errors()
                break
        return self._q_arm(), position_error, orientation_error, steps

    def solve(
        self,
        T_base_palm: ArrayLike,
        q_seed: ArrayLike | None = None,
        q_hand: Mapping[str, float] | None = None,
    ) -> IkSolution:
        """Arm joints [rad] that put the palm frame at T_base_palm (4x4, arm base frame).

        q_seed: [rad] warm start (default arm.home_q); a seed outside the limits is moved
            onto them (it is only a starting point; the solution is always checked).
        q_hand: [rad] hand joint values held fixed (default: each joint's value nearest 0).
        Raises UnreachableError when no attempt gets within the acceptance thresholds.
        """
        T_base_palm = as_pose(T_base_palm, "T_base_palm")
        q_seed = self.home_q if q_seed is None else self._check_q_arm(q_seed, "q_seed")
        q_seed = np.clip(q_seed, self.lower, self.upper)
        q_hand_full = self._q_hand_default if q_hand is None else self._full_hand_q(q_hand)
        self._task.T_world_frame = self._T_world_base @ T_base_palm

        best: tuple[NDArray[np.float64], float, float] | None = None
        iterations = attempts = 0
        for q_start in self._seeds(q_seed):
            attempts += 1
            q, position_error, orientation_error, steps = self._descend(q_start, q_hand_full)
            iterations += steps
            if best is None or _score(position_error, orientation_error) < _score(*best[1:]):
                best = (q, position_error, orientation_error)
            if (
                position_error < self.position_tolerance
                and orientation_error < self.orientation_tolerance
            ):
                break
        assert best is not None
        q, position_error, orientation_error = best
        if position_error > ACCEPT_POSITION_ERROR or orientation_error > ACCEPT_ORIENTATION_ERROR:
            raise UnreachableError(
                f"{self.robot.name}: palm target {describe_pose(T_base_palm)} is unreachable: "
                f"best of {attempts} attempts misses it by {1000 * position_error:.1f} mm and "
                f"{math.degrees(orientation_error):.2f} deg (accepted: "
                f"{1000 * ACCEPT_POSITION_ERROR:.1f} mm, "
                f"{math.degrees(ACCEPT_ORIENTATION_ERROR):.1f} deg)"
            )
        self._check_limits(q)
        q.setflags(write=False)
        return IkSolution(q, float(position_error), float(orientation_error), iterations, attempts)

    def _check_limits(self, q_arm: NDArray[np.float64]) -> None:
        outside = [
            f"{spec.name} = {value:.6f} rad not in [{spec.lower:.6f}, {spec.upper:.6f}]"
            for spec, value in zip(self.arm.joints, q_arm, strict=True)
            if not spec.lower <= value <= spec.upper
        ]
        if outside:
            raise IkLimitError(
                f"{self.robot.name}: IK solution outside the limits: {'; '.join(outside)}"
            )


def _score(position_error: float, orientation_error: float) -> float:
    """Attempts are ranked by the larger of the two errors relative to its threshold."""
    return max(position_error / ACCEPT_POSITION_ERROR, orientation_error / ACCEPT_ORIENTATION_ERROR)
