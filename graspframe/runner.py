"""One grasp run: human grasp -> plan -> execution on the arm -> score -> result.json.

The scene: the arm base at the world origin on the table top (z = 0), the object
standing on the table at SCENE_OBJECT_XY. It sits off the arm's x axis on purpose: a side
grasp straight ahead would point the flange along the forearm, a wrist singularity.
"""

from __future__ import annotations

import logging
import time
import traceback
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from graspframe.defaults import (
    MOUNT_ARM,
    MOUNT_FLOATING,
    SCENE_OBJECT_XY,
    TABLE_HEIGHT,
)
from graspframe.errors import GraspframeError, OutputError
from graspframe.events import (
    CLASSIFY_DONE,
    CLASSIFY_IMAGES,
    MOTION_CYCLE,
    PLAN_DONE,
    SCORE_DONE,
    WORLD_BUILT,
    EventKind,
    RunEvent,
    RunInfo,
)
from graspframe.files import atomic_write
from graspframe.grasps import PALM, HumanGrasp
from graspframe.hal.drivers import World, WorldConfig
from graspframe.motion.arm_motion import ArmMotion
from graspframe.registry import Registry, default_registry
from graspframe.results import new_run_dir, versions, write_json
from graspframe.run_request import RunInputs, RunRequest, resolve
from graspframe.run_result import (
    Classification,
    HumanGraspInput,
    RunResult,
    Score,
    ServoReport,
    plan_json,
)
from graspframe.scoring import score_grasp
from graspframe.snapshots import draw_grasp
from graspframe.strategy.arm_path import CheckedPlan, choose_plan, floating_plan
from graspframe.strategy.execution import Execution, GraspPolicy, execute
from graspframe.strategy.held_test import object_probe
from graspframe.strategy.method import MethodStrategy
from graspframe.strategy.reference_poses import reference_placement
from graspframe.transforms import make_T

log = logging.getLogger(__name__)


Progress = Callable[[str], None]


@dataclass
class _Recorder:
    """Collects events for result.json and forwards them to the observer plugins."""

    registry: Registry
    run: RunInfo
    events: list[dict] = field(default_factory=list)
    clock: Callable[[], float | None] = lambda: None

    def emit(self, kind: EventKind, **data: Any) -> None:
        """Send an event of a declared kind; its payload must match the declaration."""
        kind.check(data)
        event = RunEvent(kind.name, self.clock(), data)
        if not kind.observer_only:
            self.events.append({"kind": kind.name, "sim_time": event.sim_time, **data})
        self.registry.notify_run_event(self.run, event)


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
    recorder = _Recorder(registry, run)
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


def _human_grasp(
    request: RunRequest,
    inputs: RunInputs,
    registry: Registry,
    recorder: _Recorder,
    progress: Progress,
) -> HumanGraspInput:
    """The human grasp relative to the object and where the object is, from the stated
    grasp or from the image."""
    obj, human = inputs.obj, inputs.human
    if request.grasp is not None:  # stated: no image to classify
        placement = reference_placement(obj, human.preshape_for(request.grasp))
        T_world_object = make_T(p=[*SCENE_OBJECT_XY, TABLE_HEIGHT + obj.half_height])
        return HumanGraspInput(request.grasp, placement.T_object_palm, T_world_object)

    scene, image = inputs.scene, inputs.image
    assert scene is not None and image is not None  # resolve() reads both without a grasp
    progress(f"classifying the image with {request.classifier}")
    classifier = registry.get_classifier(request.classifier)()
    estimate = classifier.classify(image)
    grasp = estimate.grasp
    R_object_palm = scene.T_camera_object[:3, :3].T @ estimate.R_camera_palm
    placement = reference_placement(obj, human.preshape_for(grasp))
    if estimate.p_camera_palm is not None:
        p_object_palm = scene.T_camera_object[:3, :3].T @ (
            np.asarray(estimate.p_camera_palm) - scene.T_camera_object[:3, 3]
        )
    else:  # the object sits where the estimated posture holds it
        p_object_palm = -R_object_palm @ placement.p_palm_grasp
    T_object_palm = make_T(R_object_palm, p_object_palm)
    classification = Classification(
        classifier=request.classifier,
        grasp=grasp,
        confidence=estimate.confidence,
        R_camera_palm=estimate.R_camera_palm,
        p_camera_palm=estimate.p_camera_palm,
        neighbours=tuple(estimate.neighbours),
        T_object_palm=T_object_palm,
    )
    recorder.emit(CLASSIFY_DONE, **classification.to_json())
    recorder.emit(CLASSIFY_IMAGES, image_bgr=inputs.image, pictures=estimate.pictures)
    return HumanGraspInput(grasp, T_object_palm, scene.T_world_object, classification)


def _plan(
    request: RunRequest,
    inputs: RunInputs,
    human: HumanGraspInput,
    T_world_object_est: NDArray[np.float64],
) -> CheckedPlan:
    """The grasp plan, its path checked on the arm or on the floating base."""
    if request.mount == MOUNT_FLOATING:
        return floating_plan(
            human.grasp, human.T_object_palm, T_world_object_est, inputs.hand, inputs.obj,
            TABLE_HEIGHT, held=inputs.held_test,
        )  # fmt: skip
    return choose_plan(
        human.grasp,
        human.T_object_palm,
        T_world_object_est,
        inputs.hand,
        inputs.arm,
        inputs.obj,
        TABLE_HEIGHT,
        T_world_base=np.eye(4),
        held=inputs.held_test,
    )


def _run_stages(
    request: RunRequest,
    inputs: RunInputs,
    registry: Registry,
    recorder: _Recorder,
    stages: _Stages,
    progress: Progress,
) -> None:
    """The run's stages in order, each result kept in `stages`: the human grasp, the
    plan, the execution in a world built for it, its pictures, and the score against
    the human reference."""
    stages.human = human = _human_grasp(request, inputs, registry, recorder, progress)
    T_world_object_est = human.T_world_object.copy()
    T_world_object_est[:2, 3] += request.object_error

    progress(
        f"planning the {inputs.hand.name} grasp for a human {human.grasp.value} "
        f"({request.mount} mount)"
    )
    stages.plan = checked = _plan(request, inputs, human, T_world_object_est)
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
    policy = _policy(inputs, checked, config, T_world_object_est)
    stages.execution = execution = _execute_in_world(
        inputs, checked, config, policy, T_world_object_est, recorder, progress
    )
    stages.servo = _servo_report(policy, recorder.run.out_dir, inputs, checked)
    stages.snapshots = _draw_snapshots(
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


def _policy(
    inputs: RunInputs,
    checked: CheckedPlan,
    config: WorldConfig,
    T_world_object_est: NDArray[np.float64],
) -> GraspPolicy:
    """The run's strategy, driving the segments the plan was checked with (its executor
    settings): the method's, or the servo strategy when the request names a camera for
    it (`RunInputs.camera_cls`), its head camera looking at the believed object
    position."""
    plan, params = checked.plan, checked.executor_params
    if inputs.camera_cls is None:
        return MethodStrategy(plan, inputs.hand, inputs.obj, params)
    from graspframe.strategy.servo import ServoStrategy, head_camera

    return ServoStrategy(
        plan,
        inputs.hand,
        inputs.obj,
        config,
        inputs.camera_cls,
        head_camera(T_world_object_est[:3, 3]),
        T_world_object_est,
        params=params,
        seed=config.seed,
        noise_scale=inputs.camera_noise,
    )


def _execute_in_world(
    inputs: RunInputs,
    checked: CheckedPlan,
    config: WorldConfig,
    policy: GraspPolicy,
    T_world_object_est: NDArray[np.float64],
    recorder: _Recorder,
    progress: Progress,
) -> Execution:
    """Build the world and execute the plan in it with `policy`, judged by the run's held
    test."""
    plan = checked.plan
    progress("building the world")
    worlds: list[World] = []

    def on_world(world: World) -> None:
        worlds.append(world)
        recorder.clock = lambda: world.time
        recorder.emit(
            WORLD_BUILT,
            hand=inputs.hand.name,
            arm=checked.robot.arm.name,
            arm_joint_names=checked.robot.arm.joint_names,
            object=inputs.obj.name,
            model=checked.robot.model,
            T_world_arm_base=config.T_world_arm_base,
            T_world_object=config.T_world_object,
            T_world_object_est=T_world_object_est,
            table_height=TABLE_HEIGHT,
        )
        if world.arm is None:
            raise GraspframeError("the world was built without the arm that moves the hand")
        progress(f"executing the {plan.preshape} preshape ({plan.approach} approach)")

    def on_cycle(motion: ArmMotion) -> None:
        world = worlds[0]
        assert world.arm is not None  # on_world refused a world without one
        T_world_palm = world.hand.T_world_palm()
        recorder.emit(
            MOTION_CYCLE,
            q_arm=world.arm.joint_positions(),
            q_hand=world.hand.joint_positions(),
            T_world_palm=T_world_palm,
            T_world_object=object_probe(world).T_world_object(),
            # Contacts now; reading the palm sensor would consume its latched touch.
            palm_touched=any(c.real_finger == PALM for c in world.hand.contacts()),
            distance_to_goal=float(
                np.linalg.norm(T_world_palm[:3, 3] - plan.T_world_palm_goal[:3, 3])
            ),
        )

    return execute(
        inputs.backend_cls(),
        config,
        policy,
        inputs.held_test,
        emit=recorder.emit,
        on_world=on_world,
        on_cycle=on_cycle,
    )


def _servo_report(
    policy: GraspPolicy, run_dir: str, inputs: RunInputs, checked: CheckedPlan
) -> ServoReport | None:
    """The servo strategy's measurements and their picture, servo.png (None for the
    method's strategy)."""
    from graspframe.strategy.servo import ServoStrategy

    if not isinstance(policy, ServoStrategy) or not policy.images:
        return None
    from graspframe.perception.localise import ObjectModel
    from graspframe.perception.servo_picture import draw_servo_picture

    title = (
        f"{inputs.hand.name}: {checked.plan.preshape} on {inputs.obj.name}, "
        "the servo strategy's depth camera"
    )
    model = ObjectModel(inputs.obj, policy.seed)
    picture = draw_servo_picture(policy.images, model, title, Path(run_dir) / "servo.png")
    return ServoReport(tuple(policy.steps), picture)


def _draw_snapshots(
    run_dir: str,
    checked: CheckedPlan,
    config: WorldConfig,
    execution: Execution,
    grasp: HumanGrasp,
) -> Path | None:
    """snapshots.png in the run folder: the robot, object, table and contacts at first
    contact, hold and after the lift (None when nothing was captured)."""
    if not execution.moments:
        return None
    robot, outcome, obj = checked.robot, execution.outcome, config.object
    assert obj is not None  # a run's world always holds its object
    what = (
        f"{robot.hand.name} on {robot.arm.name}: human {grasp.value} -> "
        f"{checked.plan.preshape}, {obj.name}"
    )
    path = Path(run_dir) / "snapshots.png"
    return draw_grasp(
        path, robot, checked.T_world_base, obj, config.table_height, execution.moments, what,
        outcome.success, outcome.failure_reason,
    )  # fmt: skip
