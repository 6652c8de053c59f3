"""One grasp run: human grasp -> plan -> execution on the arm -> score -> result.json.

`run_grasp` makes the run folder, runs the stages in order (their bodies are in
run_stages.py; the score in scoring.py), keeps what each produced and writes result.json
from the typed `RunResult`, also when a stage failed or the run was interrupted.

The scene: the arm base at the world origin on the table top (z = 0), the object
standing on the table at SCENE_OBJECT_XY. It sits off the arm's x axis on purpose: a side
grasp straight ahead would point the flange along the forearm, a wrist singularity.
"""

from __future__ import annotations

import logging
import time
import traceback
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path

from graspframe import run_stages
from graspframe.defaults import (
    MOUNT_ARM,
    TABLE_HEIGHT,
)
from graspframe.errors import OutputError
from graspframe.events import (
    PLAN_DONE,
    SCORE_DONE,
    RunInfo,
)
from graspframe.files import atomic_write
from graspframe.hal.drivers import WorldConfig
from graspframe.registry import Registry, default_registry
from graspframe.results import new_run_dir, versions, write_json
from graspframe.run_request import RunInputs, RunRequest, resolve
from graspframe.run_result import (
    HumanGraspInput,
    RunResult,
    Score,
    ServoReport,
    plan_json,
)
from graspframe.run_stages import Progress
from graspframe.scoring import score_grasp
from graspframe.strategy.arm_path import CheckedPlan
from graspframe.strategy.execution import Execution

log = logging.getLogger(__name__)


@dataclass
class _Stages:
    """What the stages have produced so far (the result is written from it in every
    case, also when a stage raised)."""

    human: HumanGraspInput | None = None
    plan: CheckedPlan | None = None
    execution: Execution | None = None
    snapshots: Path | None = None
    score: Score | None = None
    human_reference_picture: Path | None = None
    servo: ServoReport | None = None


def run_grasp(
    request: RunRequest,
    registry: Registry | None = None,
    progress: Progress | None = None,
    inputs: RunInputs | None = None,
) -> RunResult:
    """Run one grasp and write runs/<id>/result.json; returns the result.

    inputs: `resolve(request, registry)` when the caller has checked the request already
    (the command line does, before it imports this module); else resolved here.
    A failure after the run folder exists is recorded (status "failed", the error; an
    interruption by Ctrl-C or SIGTERM: status "interrupted") and re-raised; so is an
    observer that cannot write its files (OutputError). result.json is written first
    with status "running" and rewritten atomically at the end, so it claims success only
    when the whole run, its files included, succeeded.
    """
    registry = registry or default_registry()
    progress = progress or (lambda message: None)
    inputs = inputs or resolve(request, registry)
    label = request.grasp.value if request.grasp else Path(request.image or "demo").stem
    run_dir = new_run_dir(request.out_root, f"{inputs.hand.name}-{label}")
    arm = inputs.arm if request.mount == MOUNT_ARM else None
    run = RunInfo(
        run_dir.name, str(run_dir), asdict(request), hand=inputs.hand, arm=arm, object=inputs.obj
    )
    recorder = run_stages.Recorder(registry, run)
    result = RunResult(run.run_id, request, versions(), Path(run_dir) / "result.json")
    write_json(result.result_path, result.to_json())
    stages = _Stages()
    started = time.perf_counter()
    failure: BaseException | None = None
    try:
        registry.notify_run_started(run)
        _run_stages(request, inputs, registry, recorder, stages, progress)
    except BaseException as exc:  # recorded, then re-raised below
        failure = exc
    result = replace(
        result,
        wall_time=time.perf_counter() - started,
        events=tuple(recorder.events),
        **asdict_shallow(stages),
    )
    result = _ended(result, failure)
    try:
        # Observers say what they wrote (the recorder: where its recording is).
        result = replace(result, artifacts=registry.notify_run_finished(run, result))
    except OutputError as exc:  # an observer's file is missing: the run failed
        failure = failure or exc
        result = _ended(result, failure)
    try:
        write_json(result.result_path, result.to_json())
    except OutputError:
        if failure is None:
            raise
        # The run's own failure is the news; result.json still says "running".
    if failure is not None:
        raise failure
    return result


def _ended(result: RunResult, failure: BaseException | None) -> RunResult:
    """`result` with the status, error and traceback of a run that ended with `failure`
    (None: it succeeded)."""
    if failure is None:
        return replace(result, status="ok", error=None, traceback=None)
    if isinstance(failure, KeyboardInterrupt):  # Ctrl-C or SIGTERM (the CLI names which)
        return replace(result, status="interrupted", error=f"interrupted ({failure or 'SIGINT'})")
    error = f"{type(failure).__name__}: {failure}"
    trace = "".join(traceback.format_exception(failure))
    return replace(result, status="failed", error=error, traceback=trace)


def asdict_shallow(stages: _Stages) -> dict:
    """The stages' fields by name (not converted, unlike dataclasses.asdict)."""
    return {f.name: getattr(stages, f.name) for f in fields(stages)}


def _run_stages(
    request: RunRequest,
    inputs: RunInputs,
    registry: Registry,
    recorder: run_stages.Recorder,
    stages: _Stages,
    progress: Progress,
) -> None:
    """The run's stages in order, each result kept in `stages`: the human grasp, the
    plan, the execution in a world built for it, its pictures, and the score against
    the human reference."""
    stages.human = human = run_stages.human_grasp(request, inputs, registry, recorder, progress)
    T_world_object_est = human.T_world_object.copy()
    T_world_object_est[:2, 3] += request.object_error

    progress(
        f"planning the {inputs.hand.name} grasp for a human {human.grasp.value} "
        f"({request.mount} mount)"
    )
    stages.plan = checked = run_stages.plan(request, inputs, human, T_world_object_est)
    recorder.emit(PLAN_DONE, **plan_json(checked))

    config = WorldConfig(
        hand=inputs.hand,
        object=inputs.obj,
        robot=checked.robot,
        T_world_arm_base=checked.T_world_base,
        T_world_object=human.T_world_object,
        table_height=TABLE_HEIGHT,
        seed=request.seed,
    )
    policy = run_stages.choose_policy(inputs, checked, config, T_world_object_est)
    stages.execution = execution = run_stages.execute_in_world(
        inputs, checked, config, policy, T_world_object_est, recorder, progress
    )
    stages.servo = run_stages.servo_report(policy, recorder.run.out_dir, inputs, checked)
    stages.snapshots = run_stages.draw_run_snapshots(
        recorder.run.out_dir, checked, config, execution, human.grasp
    )

    progress("scoring against the human reference")
    stages.score, reference = score_grasp(inputs, human.grasp, checked, execution.outcome)
    if reference.picture is not None:
        # The human grasp's picture beside the robot's snapshots.png.
        picture = Path(recorder.run.out_dir) / "human_reference.png"
        stages.human_reference_picture = atomic_write(picture, reference.picture.read_bytes())
    recorder.emit(
        SCORE_DONE,
        score=stages.score.to_json(),
        human_contacts=list(stages.score.human_contacts),
        robot_contacts_object=list(stages.score.robot_contacts),
    )
