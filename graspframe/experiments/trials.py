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
from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields
from multiprocessing.connection import Connection
from typing import Any

from graspframe.common.defaults import DEFAULT_ARM, MOUNT_ARM, STRATEGY_METHOD, Mount, Strategy
from graspframe.common.grasps import HumanGrasp
from graspframe.strategy.held_check import HELD_TEST_GRASPFRAME

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
    method's, with camera_noise, the multiple of the camera's noise, when not 1);
    held_test: "graspframe" or "benchmark" (part of the trial id when not graspframe's)."""

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
    held_test: str = HELD_TEST_GRASPFRAME

    @property
    def trial_id(self) -> str:
        base = f"{self.mount}/{self.hand}/{self.grasp}/{self.condition}"
        chosen = swept_object(self.condition, self.object)
        base = base if chosen is None else f"{base}/{chosen}"
        if self.strategy != STRATEGY_METHOD:
            noise = "" if self.camera_noise == 1.0 else f"-noise{self.camera_noise:g}"
            base = f"{base}/{self.strategy}{noise}"
        if self.held_test != HELD_TEST_GRASPFRAME:
            base = f"{base}/{self.held_test}-held"
        return base


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


STATUS_OK = "ok"
STATUS_FAILED = "failed"


@dataclass(frozen=True)
class TrialRow:
    """What one trial gave: its spec, "ok" with the numbers the summary needs or
    "failed" with the error, and its wall time [s] (None: unknown, a lost Dask worker).

    The numbers (None for a failed trial): result_path: the run's result.json; success,
    held_after_lift, held_under_disturbance, failure_reason, touching_fingers,
    corrections, palm_contact: the grasp (result.json's outcome); position_err_mm,
    orientation_err_deg, robot_vf, human_vf, score_error: the virtual-finger score;
    robot_epsilon, human_epsilon, robot_volume, human_volume: Ferrari-Canny L1 quality
    and wrench space volume; human_held: the human reference's held test;
    limit_excess_deg, limit_violations: the joints past their model limits.

    One line of trials.jsonl is `to_json()`: "trial_id", the spec's fields, "status",
    the numbers (ok) or "error" (failed), "wall_time"; `from_json` reads it back.
    """

    spec: TrialSpec
    status: str
    error: str | None = None
    result_path: str | None = None
    success: bool | None = None
    held_after_lift: bool | None = None
    held_under_disturbance: bool | None = None
    failure_reason: str | None = None
    touching_fingers: tuple[str, ...] | None = None
    corrections: int | None = None
    palm_contact: bool | None = None
    position_err_mm: float | None = None
    orientation_err_deg: float | None = None
    robot_vf: int | None = None
    human_vf: int | None = None
    score_error: str | None = None
    robot_epsilon: float | None = None
    human_epsilon: float | None = None
    robot_volume: float | None = None
    human_volume: float | None = None
    human_held: bool | None = None
    limit_excess_deg: float | None = None
    limit_violations: tuple[str, ...] | None = None
    wall_time: float | None = None

    @property
    def trial_id(self) -> str:
        return self.spec.trial_id

    @property
    def ok(self) -> bool:
        return self.status == STATUS_OK

    def to_json(self) -> dict[str, Any]:
        """The trials.jsonl line's values."""
        data: dict[str, Any] = {"trial_id": self.trial_id, **asdict(self.spec)}
        if data["held_test"] == HELD_TEST_GRASPFRAME:
            del data["held_test"]  # the lines of graspframe's held test read as they always have
        data["status"] = self.status
        if self.ok:
            for name in _NUMBERS:
                value = getattr(self, name)
                data[name] = list(value) if isinstance(value, tuple) else value
        else:
            data["error"] = self.error
        data["wall_time"] = self.wall_time
        return data

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> TrialRow:
        """The row of a trials.jsonl line (KeyError, TypeError or ValueError when it is
        not one); a spec field missing from an older line takes its default."""
        spec_values = {f.name: data[f.name] for f in fields(TrialSpec) if f.name in data}
        spec_values["object_error"] = tuple(spec_values["object_error"])
        numbers: dict[str, Any] = {}
        for name in _NUMBERS:
            value = data.get(name)
            numbers[name] = tuple(value) if isinstance(value, list) else value
        return cls(
            spec=TrialSpec(**spec_values),
            status=str(data["status"]),
            error=data.get("error"),
            wall_time=data.get("wall_time"),
            **numbers,
        )


# The numbers of a trial that ran, in the order of its trials.jsonl line.
_NUMBERS = tuple(
    f.name for f in fields(TrialRow) if f.name not in ("spec", "status", "error", "wall_time")
)


def run_trial(spec: TrialSpec) -> TrialRow:
    """Run the grasp of `spec` in this process; the row of numbers for the summary."""
    from graspframe.run.request import RunRequest
    from graspframe.run.runner import run_grasp

    started = time.perf_counter()
    request = RunRequest(
        hand=spec.hand,
        grasp=HumanGrasp.parse(spec.grasp),
        arm=spec.arm,
        mount=Mount.parse(spec.mount),
        object=spec.object,
        object_error=spec.object_error,
        seed=spec.seed,
        out_root=spec.runs_dir,
        record=spec.record,
        strategy=Strategy.parse(spec.strategy),
        camera_noise=spec.camera_noise,
        held_test_name=spec.held_test,
    )
    try:
        result = run_grasp(request)
    except Exception as exc:
        return failed_row(spec, f"{type(exc).__name__}: {exc}", time.perf_counter() - started)
    outcome, score = result.outcome, result.score
    if outcome is None:  # run_grasp either raises or executes the grasp
        raise RuntimeError(f"run {result.run_id} ended without executing the grasp")
    assert result.execution is not None  # an outcome comes with its execution
    joint_limits = result.execution.joint_limits
    comparison = None if score is None else score.comparison
    robot_quality = None if score is None else score.quality_robot.measured
    human_quality = None if score is None else score.quality_human.measured
    human_held = None if score is None or score.human_held is None else score.human_held.held
    return TrialRow(
        spec=spec,
        status=STATUS_OK,
        result_path=str(result.result_path),
        success=outcome.success,
        held_after_lift=outcome.held_after_lift,
        held_under_disturbance=outcome.held_under_disturbance,
        failure_reason=outcome.failure_reason,
        touching_fingers=tuple(outcome.touching_fingers),
        corrections=outcome.corrections,
        palm_contact=outcome.palm_contact,
        position_err_mm=None if comparison is None else comparison.position_err_mm,
        orientation_err_deg=None if comparison is None else comparison.orientation_err_deg,
        robot_vf=None if comparison is None else comparison.robot_count,
        human_vf=None if comparison is None else comparison.human_count,
        score_error=None if score is None else score.error,
        robot_epsilon=None if robot_quality is None else robot_quality.epsilon_l1,
        human_epsilon=None if human_quality is None else human_quality.epsilon_l1,
        robot_volume=None if robot_quality is None else robot_quality.volume_l1,
        human_volume=None if human_quality is None else human_quality.volume_l1,
        human_held=human_held,
        limit_excess_deg=joint_limits.largest_excess_deg,
        limit_violations=tuple(e.joint for e in joint_limits.violations),
        wall_time=time.perf_counter() - started,
    )


def _child(spec: TrialSpec, connection: Connection) -> None:
    connection.send(run_trial(spec))
    connection.close()


def run_trial_isolated(spec: TrialSpec, time_limit: float = TRIAL_TIME_LIMIT) -> TrialRow:
    """`run_trial` in a fresh process; a crash or a time-out gives a failed row."""
    context = multiprocessing.get_context("spawn")
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(target=_child, args=(spec, sender), daemon=False)
    started = time.perf_counter()
    process.start()
    sender.close()
    row: TrialRow | None = None
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


def failed_row(spec: TrialSpec, error: str, wall_time: float | None) -> TrialRow:
    """The row of a failed trial; wall_time [s]."""
    return TrialRow(spec, STATUS_FAILED, error=error, wall_time=wall_time)
