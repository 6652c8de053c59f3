"""One trial of an experiment: a grasp run reduced to the numbers the summary needs.

A trial runs in a process apart from the sweep, so a crash or a hang in the simulator
costs that trial only: `run_trial_isolated` spawns a fresh process for one trial (the
Dask executor, single use), `workers.run_in_workers` keeps a few processes for a whole
sweep (the local executor). Both wait up to a time limit, kill past it, and return a row
that says what happened in every case.
"""

from __future__ import annotations

import math
import multiprocessing
import time
from dataclasses import asdict, dataclass
from multiprocessing.connection import Connection

from graspframe.defaults import DEFAULT_ARM, MOUNT_ARM, STRATEGY_METHOD
from graspframe.grasps import HumanGrasp

CONDITION_A = "A"
TRIAL_TIME_LIMIT = 300.0  # [s] wall time before a trial is killed and recorded as failed


@dataclass(frozen=True)
class TrialSpec:
    """hand, grasp; condition "A" (perfect perception), "B<k>" (object error rho in
    direction beta_k) or "A<size>" (perfect perception on the object scaled to <size>
    percent, e.g. "A075"); object_error: [m] (dx, dy) the robot adds to the object
    position; object: the object's name (None: the grasp's default object; with "A" or
    "B<k>" it is part of the trial id: a sweep over objects); mount: "arm" or
    "floating"; record: write a rerun recording of the trial (off by default: sweeps are
    for numbers); strategy: "method" or "servo" (part of the trial id when not the
    method's, with camera_noise, the multiple of the camera's noise, when not 1)."""

    hand: str
    grasp: str
    condition: str
    object_error: tuple[float, float]
    seed: int
    runs_dir: str
    arm: str = DEFAULT_ARM
    record: bool = False
    mount: str = MOUNT_ARM
    object: str | None = None
    strategy: str = STRATEGY_METHOD
    camera_noise: float = 1.0

    @property
    def trial_id(self) -> str:
        base = f"{self.mount}/{self.hand}/{self.grasp}/{self.condition}"
        chosen = swept_object(self.condition, self.object)
        base = base if chosen is None else f"{base}/{chosen}"
        if self.strategy == STRATEGY_METHOD:
            return base
        noise = "" if self.camera_noise == 1.0 else f"-noise{self.camera_noise:g}"
        return f"{base}/{self.strategy}{noise}"


def swept_object(condition: str, object_name: str | None) -> str | None:
    """The object a trial of a sweep over objects ran on; None for the catalogue's
    trials (the grasp's default object, or its scaled variant of an "A<size>" condition,
    which the condition names)."""
    if object_name is None or (condition.startswith(CONDITION_A) and condition != CONDITION_A):
        return None
    return object_name


def experiment_b_errors(rho: float, directions: int) -> list[tuple[str, tuple[float, float]]]:
    """[(condition, (dx, dy))] for beta_k = 2 pi k / directions, k = 0..directions-1."""
    errors = []
    for k in range(directions):
        beta = 2.0 * math.pi * k / directions
        errors.append((f"B{k}", (rho * math.cos(beta), rho * math.sin(beta))))
    return errors


def run_trial(spec: TrialSpec) -> dict:
    """Run the grasp of `spec` in this process; the row of numbers for the summary."""
    from graspframe.run_request import RunRequest
    from graspframe.runner import run_grasp

    started = time.perf_counter()
    request = RunRequest(
        hand=spec.hand,
        grasp=HumanGrasp.parse(spec.grasp),
        arm=spec.arm,
        mount=spec.mount,
        object=spec.object,
        object_error=spec.object_error,
        seed=spec.seed,
        out_root=spec.runs_dir,
        record=spec.record,
        strategy=spec.strategy,
        camera_noise=spec.camera_noise,
    )
    row = {"trial_id": spec.trial_id, **asdict(spec)}
    try:
        result = run_grasp(request)
    except Exception as exc:
        row.update(status="failed", error=f"{type(exc).__name__}: {exc}")
        row["wall_time"] = time.perf_counter() - started
        return row
    outcome, score = result.outcome, result.score
    if outcome is None:  # run_grasp either raises or executes the grasp
        raise RuntimeError(f"run {result.run_id} ended without executing the grasp")
    assert result.execution is not None  # an outcome comes with its execution
    joint_limits = result.execution.joint_limits
    comparison = None if score is None else score.comparison
    robot_quality = {} if score is None else dict(score.quality_robot.values or {})
    human_quality = {} if score is None else dict(score.quality_human.values or {})
    human_held = None if score is None or score.human_held is None else score.human_held.held
    row.update(
        status="ok",
        result_path=str(result.result_path),
        success=outcome.success,
        held_after_lift=outcome.held_after_lift,
        held_under_disturbance=outcome.held_under_disturbance,
        failure_reason=outcome.failure_reason,
        touching_fingers=outcome.touching_fingers,
        corrections=outcome.corrections,
        palm_contact=outcome.palm_contact,
        position_err_mm=None if comparison is None else comparison.position_err_mm,
        orientation_err_deg=None if comparison is None else comparison.orientation_err_deg,
        robot_vf=None if comparison is None else comparison.robot_count,
        human_vf=None if comparison is None else comparison.human_count,
        score_error=None if score is None else score.error,
        robot_epsilon=robot_quality.get("epsilon_l1"),
        human_epsilon=human_quality.get("epsilon_l1"),
        robot_volume=robot_quality.get("volume_l1"),
        human_volume=human_quality.get("volume_l1"),
        human_held=human_held,
        limit_excess_deg=joint_limits.largest_excess_deg,
        limit_violations=[e.joint for e in joint_limits.violations],
        wall_time=time.perf_counter() - started,
    )
    return row


def _child(spec: TrialSpec, connection: Connection) -> None:
    connection.send(run_trial(spec))
    connection.close()


def run_trial_isolated(spec: TrialSpec, time_limit: float = TRIAL_TIME_LIMIT) -> dict:
    """`run_trial` in a fresh process; a crash or a time-out gives a failed row."""
    context = multiprocessing.get_context("spawn")
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(target=_child, args=(spec, sender), daemon=False)
    started = time.perf_counter()
    process.start()
    sender.close()
    row = None
    if receiver.poll(time_limit):
        try:
            row = receiver.recv()
        except EOFError:  # the child died while sending
            row = None
    if process.is_alive():
        process.kill()
    process.join()
    if row is not None:
        return row
    elapsed = time.perf_counter() - started
    if elapsed >= time_limit:
        return failed_row(spec, timed_out_error(time_limit), elapsed)
    return failed_row(spec, died_error(process.exitcode), elapsed)


def timed_out_error(time_limit: float) -> str:
    """The error of a trial killed past its time limit [s]."""
    return f"timed out after {time_limit:.0f} s"


def died_error(exit_code: int | None) -> str:
    """The error of a trial whose process ended without a row (a crash, a kill)."""
    return f"the trial process died (exit code {exit_code})"


def failed_row(spec: TrialSpec, error: str, wall_time: float) -> dict:
    """The row of a trial that gave no row of its own; wall_time [s]."""
    return {
        "trial_id": spec.trial_id,
        **asdict(spec),
        "status": "failed",
        "error": error,
        "wall_time": wall_time,
    }
