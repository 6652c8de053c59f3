"""One grasp run: human grasp -> plan -> execution on the arm -> score -> result.json.

`run_grasp` makes the run folder, runs the stages in order (their bodies are in
stages.py; the score in scoring.py), keeps what each produced and writes result.json
from the typed `RunResult`, also when a stage failed or the run was interrupted.

The scene: the arm base at the world origin on the table top (z = 0), the object
standing on the table at SCENE_OBJECT_XY. It sits off the arm's x axis on purpose: a side
grasp straight ahead would point the flange along the forearm, a wrist singularity.
"""

from __future__ import annotations

import logging
import time
import traceback
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

from graspframe.common.defaults import (
    MOUNT_ARM,
    TABLE_HEIGHT,
)
from graspframe.common.errors import OutputError
from graspframe.common.files import atomic_write
from graspframe.common.json_files import write_json
from graspframe.hal.drivers import WorldConfig
from graspframe.plugin_system.events import (
    PLAN_DONE,
    SCORE_DONE,
    RunInfo,
)
from graspframe.plugin_system.registry import Registry, default_registry
from graspframe.run import stages as run_stages
from graspframe.run.folder import new_run_dir, versions
from graspframe.run.request import RunInputs, RunRequest, resolve
from graspframe.run.result import RunResult, StageOutputs, plan_json
from graspframe.run.scoring import score_grasp
from graspframe.run.stages import Progress

log = logging.getLogger(__name__)


class _StagesSoFar:
    """The stages' outputs as they come (kept when a stage raises: the result is written
    from them in every case)."""

    def __init__(self) -> None:
        self.outputs = StageOutputs()

    def keep(self, **outputs: Any) -> None:
        self.outputs = replace(self.outputs, **outputs)


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
    result = RunResult(
        run_id=run.run_id,
        request=request,
        versions=versions(),
        result_path=Path(run_dir) / "result.json",
    )
    write_json(result.result_path, result.to_json())
    stages = _StagesSoFar()
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
        **stages.outputs.by_name(),
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


def _run_stages(
    request: RunRequest,
    inputs: RunInputs,
    registry: Registry,
    recorder: run_stages.Recorder,
    stages: _StagesSoFar,
    progress: Progress,
) -> None:
    """The run's stages in order, each result kept in `stages`: the human grasp, the
    plan, the execution in a world built for it, its pictures, and the score against
    the human reference."""
    human = run_stages.human_grasp(request, inputs, registry, recorder, progress)
    stages.keep(human=human)
    T_world_object_est = human.T_world_object.copy()
    T_world_object_est[:2, 3] += request.object_error

    progress(
        f"planning the {inputs.hand.name} grasp for a human {human.grasp.value} "
        f"({request.mount} mount)"
    )
    checked = run_stages.plan(request, inputs, human, T_world_object_est)
    stages.keep(plan=checked)
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
    execution = run_stages.execute_in_world(
        inputs, checked, config, policy, T_world_object_est, recorder, progress
    )
    stages.keep(execution=execution)
    stages.keep(servo=run_stages.servo_report(policy, recorder.run.out_dir, inputs, checked))
    snapshots = run_stages.draw_run_snapshots(
        recorder.run.out_dir, checked, config, execution, human.grasp
    )
    stages.keep(snapshots=snapshots)

    progress("scoring against the human reference")
    score, reference = score_grasp(inputs, human.grasp, checked, execution.outcome)
    stages.keep(score=score)
    if reference.picture is not None:
        # The human grasp's picture beside the robot's snapshots.png.
        picture = Path(recorder.run.out_dir) / "human_reference.png"
        stages.keep(human_reference_picture=atomic_write(picture, reference.picture.read_bytes()))
    recorder.emit(
        SCORE_DONE,
        score=score.to_json(),
        human_contacts=list(score.human_contacts),
        robot_contacts_object=list(score.robot_contacts),
    )
