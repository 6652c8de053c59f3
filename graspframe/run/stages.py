"""The stages of one grasp run (runner.py runs them in order): the human grasp from the
stated grasp or the image, the checked plan, the policy that executes it, the execution
in a world built for it, the servo strategy's report and the run's snapshots.png.
`Recorder` collects the run's events for result.json and hands them to the observers.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from graspframe.common.defaults import MOUNT_FLOATING, SCENE_OBJECT_XY, TABLE_HEIGHT
from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.common.transforms import make_T
from graspframe.hal.drivers import World, WorldConfig
from graspframe.motion.arm_motion import ArmMotion
from graspframe.pictures.snapshots import draw_grasp
from graspframe.plugin_system.events import (
    CLASSIFY_DONE,
    CLASSIFY_IMAGES,
    MOTION_CYCLE,
    WORLD_BUILT,
    EventKind,
    RunEvent,
    RunInfo,
)
from graspframe.plugin_system.registry import Registry
from graspframe.run.request import RunInputs, RunRequest
from graspframe.run.result import Classification, HumanGraspInput, ServoReport
from graspframe.strategy.arm_path import CheckedPlan, choose_plan, floating_plan
from graspframe.strategy.execution import Execution, GraspPolicy, execute
from graspframe.strategy.held_check import object_probe
from graspframe.strategy.method import MethodStrategy
from graspframe.strategy.planner import PlanningTarget
from graspframe.strategy.reference_poses import reference_placement

Progress = Callable[[str], None]


@dataclass
class Recorder:
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


def human_grasp(
    request: RunRequest,
    inputs: RunInputs,
    registry: Registry,
    recorder: Recorder,
    progress: Progress,
) -> HumanGraspInput:
    """The human grasp relative to the object and where the object is, from the stated
    grasp or from the image."""
    obj, human = inputs.obj, inputs.human
    if request.grasp is not None:  # stated: no image to classify
        placement = reference_placement(obj, human.preshape_for(request.grasp))
        T_world_object = obj.T_world_standing(SCENE_OBJECT_XY, TABLE_HEIGHT)
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


def plan(
    request: RunRequest,
    inputs: RunInputs,
    human: HumanGraspInput,
    T_world_object_est: NDArray[np.float64],
) -> CheckedPlan:
    """The grasp plan, its path checked on the arm or on the floating base."""
    target = PlanningTarget(
        human.grasp, human.T_object_palm, T_world_object_est, inputs.hand, inputs.obj,
        TABLE_HEIGHT,
    )  # fmt: skip
    if request.mount == MOUNT_FLOATING:
        return floating_plan(target, held=inputs.held_test)
    return choose_plan(
        target, inputs.arm, T_world_base=np.eye(4), held=inputs.held_test, robots=inputs.robots
    )


def choose_policy(
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


def execute_in_world(
    inputs: RunInputs,
    checked: CheckedPlan,
    config: WorldConfig,
    policy: GraspPolicy,
    T_world_object_est: NDArray[np.float64],
    recorder: Recorder,
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


def servo_report(
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


def draw_run_snapshots(
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
