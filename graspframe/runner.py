"""One grasp run: human grasp -> plan -> execution on the arm -> score -> result.json.

The scene: the arm base at the world origin on the table top (z = 0), the object
standing on the table at SCENE_OBJECT_XY. It sits off the arm's x axis on purpose: a side
grasp straight ahead would point the flange along the forearm, a wrist singularity.
"""

from __future__ import annotations

import logging
import shutil
import time
import traceback
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from graspframe.contacts import Contact
from graspframe.defaults import (
    DEFAULT_ARM,
    DEFAULT_BACKEND,
    DEFAULT_CLASSIFIER,
    MOUNT_ARM,
    MOUNT_FLOATING,
    MOUNTS,
    SCENE_OBJECT_XY,
    TABLE_HEIGHT,
)
from graspframe.errors import GraspframeError, InputError
from graspframe.events import (
    CLASSIFY_DONE,
    CLASSIFY_IMAGES,
    EXECUTE_SNAPSHOT,
    MOTION_CYCLE,
    PLAN_DONE,
    SCORE_DONE,
    WORLD_BUILT,
    EventKind,
    RunEvent,
    RunInfo,
)
from graspframe.grasps import HUMAN_HAND, PALM, HumanGrasp
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.hal.drivers import Backend, WorldConfig
from graspframe.hal.objects import ObjectDescription
from graspframe.metrics.quality import grasp_quality
from graspframe.metrics.virtual_fingers import compare, virtual_fingers_from_contacts
from graspframe.motion.arm_motion import ArmMotion
from graspframe.registry import Registry, default_registry
from graspframe.results import new_run_dir, versions, write_json
from graspframe.scene import Scene, check_on_table, load_scene
from graspframe.snapshots import Snapshot, draw_snapshots, scene_of_robot
from graspframe.strategy.arm_path import CheckedPlan, choose_plan, floating_plan
from graspframe.strategy.executor import ExecutorParams, GraspOutcome, execute_plan
from graspframe.strategy.held_test import object_probe
from graspframe.strategy.human_reference import (
    HumanReference,
    human_reference,
    load_reference_file,
)
from graspframe.strategy.reference_poses import reference_placement
from graspframe.transforms import make_T

log = logging.getLogger(__name__)

MAX_OBJECT_ERROR = 0.5  # [m] larger injected errors are surely a unit mistake


@dataclass(frozen=True)
class RunRequest:
    """What to run.

    grasp: the human grasp stated (skips vision); None: classify `image` (default: the
        bundled demo) with `classifier`, the camera and object poses from `scene`.
    object_error: [m] (dx, dy) added to the object position the robot believes (the
        object itself stays put). human_contacts: a measured-contacts file replacing the
        simulated human reference. record: stream a rerun recording of the run.
    mount: "arm" (the hand on `arm`) or "floating" (the hand alone on a free 6-DOF
        base, as in the method's grasp simulator).
    """

    hand: str
    grasp: HumanGrasp | None = None
    image: str | None = None
    scene: str | None = None
    classifier: str = DEFAULT_CLASSIFIER
    arm: str = DEFAULT_ARM
    object: str | None = None
    object_error: tuple[float, float] = (0.0, 0.0)
    seed: int = 0
    backend: str = DEFAULT_BACKEND
    out_root: str = "runs"
    human_contacts: str | None = None
    record: bool = True
    mount: str = MOUNT_ARM

    def command(self) -> str:
        """The command line that repeats this run."""
        parts = ["graspframe", "run", "--hand", self.hand]
        if self.grasp is not None:
            parts += ["--grasp", self.grasp.value]
        if self.image:
            parts += ["--image", self.image, "--scene", str(self.scene)]
        parts += ["--arm", self.arm, "--mount", self.mount, "--seed", str(self.seed)]
        if self.object:
            parts += ["--object", self.object]
        if any(self.object_error):
            dx, dy = (1000.0 * v for v in self.object_error)
            parts += ["--object-error-mm", f"{dx:g},{dy:g}"]
        if self.human_contacts:
            parts += ["--human-contacts", self.human_contacts]
        if not self.record:
            parts += ["--no-record"]
        return " ".join(parts)


Progress = Callable[[str], None]


@dataclass
class _Recorder:
    """Collects events for result.json and forwards them to the observer plugins."""

    registry: Registry
    run: RunInfo
    events: list[dict] = field(default_factory=list)
    clock: Callable[[], float | None] = lambda: None

    def emit(self, kind: EventKind, **data) -> None:
        """Send an event of a declared kind; its payload must match the declaration."""
        kind.check(data)
        event = RunEvent(kind.name, self.clock(), data)
        if not kind.observer_only:
            self.events.append({"kind": kind.name, "sim_time": event.sim_time, **data})
        self.registry.notify_run_event(self.run, event)


def demo_paths() -> tuple[Path, Path]:
    """The bundled demo image and its scene file."""
    from importlib.resources import files

    folder = Path(str(files("graspframe.demo")))
    return folder / "demo.png", folder / "scene.json"


@dataclass(frozen=True)
class _Inputs:
    """Everything a run needs, looked up and read before it starts."""

    hand: HandDescription
    arm: ArmDescription
    backend_cls: type[Backend]
    obj: ObjectDescription
    human: HandDescription
    reference_file: HumanReference | None
    scene: Scene | None
    image: np.ndarray | None


def resolve(request: RunRequest, registry: Registry) -> _Inputs:
    """Look every name up and read every input first: bad input fails before anything
    runs."""
    if request.mount not in MOUNTS:
        raise InputError(f"unknown mount {request.mount!r}; mounts: {', '.join(MOUNTS)}")
    hand = registry.get_hand(request.hand)
    arm = registry.get_arm(request.arm)
    backend_cls = registry.get_backend(request.backend)
    scene = image = None
    if request.grasp is None:
        from graspframe.vision.images import read_image

        if request.image and not request.scene:
            raise InputError("--image needs --scene (the camera and object poses of the image)")
        demo_image, demo_scene = demo_paths()
        registry.get_classifier(request.classifier)
        image = read_image(Path(request.image or demo_image))
        scene = load_scene(request.scene or demo_scene)
    if request.object:
        obj = registry.get_object(request.object)
    elif scene is not None:
        obj = registry.get_object(scene.object_name)
    else:
        assert request.grasp is not None  # without a grasp the scene names the object
        obj = registry.default_object_for(request.grasp)
    if scene is not None:
        check_on_table(scene, obj.half_height, TABLE_HEIGHT)
    if any(not np.isfinite(v) or abs(v) > MAX_OBJECT_ERROR for v in request.object_error):
        raise InputError(
            f"object error {request.object_error} m is not finite or above {MAX_OBJECT_ERROR} m"
        )
    reference_file = load_reference_file(request.human_contacts) if request.human_contacts else None
    human = registry.get_hand(HUMAN_HAND)
    return _Inputs(hand, arm, backend_cls, obj, human, reference_file, scene, image)


def run_grasp(
    request: RunRequest, registry: Registry | None = None, progress: Progress | None = None
) -> dict:
    """Run one grasp and write runs/<id>/result.json; returns the result dictionary.

    A failure after the run folder exists is recorded (status "failed", the error) and
    re-raised; the result file is written in every case.
    """
    registry = registry or default_registry()
    progress = progress or (lambda message: None)
    inputs = resolve(request, registry)
    label = request.grasp.value if request.grasp else Path(request.image or "demo").stem
    run_dir = new_run_dir(request.out_root, f"{inputs.hand.name}-{label}")
    arm = inputs.arm if request.mount == MOUNT_ARM else None
    run = RunInfo(
        run_dir.name, str(run_dir), asdict(request), hand=inputs.hand, arm=arm, object=inputs.obj
    )
    recorder = _Recorder(registry, run)
    result: dict = {
        "run_id": run.run_id,
        "status": "running",
        "request": asdict(request),
        "reproduce": request.command(),
        "seed": request.seed,
        "versions": versions(),
        "scene": {"object_xy": SCENE_OBJECT_XY, "table_height": TABLE_HEIGHT},
    }
    result_path = Path(run_dir) / "result.json"
    write_json(result_path, result)
    registry.notify_run_started(run)
    started = time.perf_counter()
    try:
        _execute(request, inputs, registry, recorder, result, progress)
        result["status"] = "ok"
    except BaseException as exc:
        result["status"] = "failed"
        result["error"] = f"{type(exc).__name__}: {exc}"
        result["traceback"] = traceback.format_exc()
        raise
    finally:
        result["wall_time"] = time.perf_counter() - started
        result["events"] = recorder.events
        result["result_path"] = str(result_path)
        # Observers may add to the result (the recorder adds where its recording is).
        registry.notify_run_finished(run, result)
        write_json(result_path, result)
    return result


def _human_grasp(request, inputs, registry, recorder, result, progress):
    """(grasp, T_object_human_palm, T_world_object): the human grasp relative to the
    object and where the object is, from the stated grasp or from the image."""
    obj, human = inputs.obj, inputs.human
    if inputs.scene is None:
        grasp = request.grasp
        placement = reference_placement(obj, human.preshape_for(grasp))
        T_world_object = make_T(p=[*SCENE_OBJECT_XY, TABLE_HEIGHT + obj.half_height])
        return grasp, placement.T_object_palm, T_world_object

    progress(f"classifying the image with {request.classifier}")
    classifier = registry.get_classifier(request.classifier)()
    estimate = classifier.classify(inputs.image)
    grasp = estimate.grasp
    scene = inputs.scene
    R_object_palm = scene.T_camera_object[:3, :3].T @ estimate.R_camera_palm
    placement = reference_placement(obj, human.preshape_for(grasp))
    if estimate.p_camera_palm is not None:
        p_object_palm = scene.T_camera_object[:3, :3].T @ (
            np.asarray(estimate.p_camera_palm) - scene.T_camera_object[:3, 3]
        )
    else:  # the object sits where the estimated posture holds it
        p_object_palm = -R_object_palm @ placement.p_palm_grasp
    T_object_palm = make_T(R_object_palm, p_object_palm)
    classification = {
        "classifier": request.classifier,
        "grasp": grasp.value,
        "confidence": estimate.confidence,
        "R_camera_palm": estimate.R_camera_palm,
        "p_camera_palm": estimate.p_camera_palm,
        "neighbours": [
            {"view_id": n.view_id, "grasp": n.grasp.value, "distance": n.distance}
            for n in estimate.neighbours
        ],
        "T_object_palm": T_object_palm,
    }
    result["classification"] = classification
    recorder.emit(CLASSIFY_DONE, **classification)
    recorder.emit(CLASSIFY_IMAGES, image_bgr=inputs.image, pictures=estimate.pictures)
    return grasp, T_object_palm, scene.T_world_object


def _plan(request, inputs, grasp, T_object_human_palm, T_world_object_est) -> CheckedPlan:
    """The grasp plan, its path checked on the arm or on the floating base."""
    if request.mount == MOUNT_FLOATING:
        return floating_plan(
            grasp, T_object_human_palm, T_world_object_est, inputs.hand, inputs.obj, TABLE_HEIGHT
        )
    return choose_plan(
        grasp,
        T_object_human_palm,
        T_world_object_est,
        inputs.hand,
        inputs.arm,
        inputs.obj,
        TABLE_HEIGHT,
        T_world_base=np.eye(4),
    )


def _execute(request, inputs, registry, recorder, result, progress) -> None:
    """The run's stages in order: the human grasp, the plan, the execution in a world
    built for it, its pictures, and the score against the human reference."""
    grasp, T_object_human_palm, T_world_object = _human_grasp(
        request, inputs, registry, recorder, result, progress
    )
    T_world_object_est = T_world_object.copy()
    T_world_object_est[:2, 3] += request.object_error

    progress(
        f"planning the {inputs.hand.name} grasp for a human {grasp.value} ({request.mount} mount)"
    )
    checked = _plan(request, inputs, grasp, T_object_human_palm, T_world_object_est)
    result["plan"] = {**checked.plan.to_dict(), "variants_refused": list(checked.refused)}
    recorder.emit(PLAN_DONE, **result["plan"])

    config = WorldConfig(
        hand=inputs.hand,
        object=inputs.obj,
        robot=checked.robot,
        T_world_arm_base=checked.T_world_base,
        T_world_object=T_world_object,
        table_height=TABLE_HEIGHT,
        seed=request.seed,
    )
    outcome, snapshots = _execute_in_world(
        inputs, checked, config, T_world_object_est, recorder, progress
    )
    result["outcome"] = _outcome_dict(outcome)
    result["snapshots"] = _draw_snapshots(
        recorder.run.out_dir, checked, config, snapshots, outcome, grasp
    )

    progress("scoring against the human reference")
    _score_run(inputs, grasp, checked, outcome, recorder, result)


def _execute_in_world(
    inputs: _Inputs,
    checked: CheckedPlan,
    config: WorldConfig,
    T_world_object_est,
    recorder: _Recorder,
    progress: Progress,
) -> tuple[GraspOutcome, list[dict]]:
    """Build the world, execute the plan in it; (outcome, the snapshot events' data)."""
    plan = checked.plan
    progress("building the world")
    snapshots: list[dict] = []
    with inputs.backend_cls().create_world(config) as world:
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

        arm, probe = world.arm, object_probe(world)
        if arm is None:
            raise GraspframeError("the world was built without the arm that moves the hand")

        def on_cycle(motion: ArmMotion) -> None:
            T_world_palm = world.hand.T_world_palm()
            recorder.emit(
                MOTION_CYCLE,
                q_arm=arm.joint_positions(),
                q_hand=world.hand.joint_positions(),
                T_world_palm=T_world_palm,
                T_world_object=probe.T_world_object(),
                # Contacts now; reading the palm sensor would consume its latched touch.
                palm_touched=any(c.real_finger == PALM for c in world.hand.contacts()),
                distance_to_goal=float(
                    np.linalg.norm(T_world_palm[:3, 3] - plan.T_world_palm_goal[:3, 3])
                ),
            )

        def emit(kind: EventKind, **data) -> None:
            if kind is EXECUTE_SNAPSHOT:
                snapshots.append(data)
            recorder.emit(kind, **data)

        motion = ArmMotion(world, checked.robot, config.T_world_arm_base, on_cycle=on_cycle)
        progress(f"executing the {plan.preshape} preshape ({plan.approach} approach)")
        outcome = execute_plan(
            plan, world, motion, inputs.hand, inputs.obj, ExecutorParams(), emit=emit
        )
    return outcome, snapshots


def _score_run(inputs, grasp, checked, outcome, recorder, result) -> None:
    """Score the robot against the human reference (result["score"]), with the human
    reference's picture beside the robot's."""
    obj, human = inputs.obj, inputs.human
    reference = inputs.reference_file or human_reference(grasp, obj, human, inputs.backend_cls())
    # A grasp turned about a symmetric object's axis is scored in the turned object frame.
    T_world_object_scored = outcome.T_world_object_at_hold @ make_T(checked.plan.R_object_symmetry)
    robot_contacts = [c.in_object_frame(T_world_object_scored) for c in outcome.contacts]
    result["score"] = _score(robot_contacts, reference, inputs.hand, human)
    if reference.picture is not None:
        # The human grasp's picture beside the robot's snapshots.png.
        picture = Path(recorder.run.out_dir) / "human_reference.png"
        shutil.copyfile(reference.picture, picture)
        result["human_reference_picture"] = str(picture)
    result["score"]["quality"] = {
        "robot": _quality(robot_contacts, obj),
        "human": _quality(list(reference.contacts), obj),
    }
    recorder.emit(
        SCORE_DONE,
        score=result["score"],
        human_contacts=list(reference.contacts),
        robot_contacts_object=robot_contacts,
    )


def _draw_snapshots(run_dir, checked, config, snapshots, outcome, grasp) -> str | None:
    """snapshots.png in the run folder: the robot, object, table and contacts at first
    contact, hold and after the lift; returns its path (None when nothing was captured)."""
    if not snapshots:
        return None
    hand, arm = config.hand, checked.robot.arm
    scene = scene_of_robot(
        checked.robot.model, checked.T_world_base, hand, config.object, config.table_height
    )
    frames = [Snapshot.from_event(data, arm.joint_names) for data in snapshots]
    verdict = "held" if outcome.success else f"failed: {outcome.failure_reason}"
    title = (
        f"{hand.name} on {arm.name}: human {grasp.value} -> {checked.plan.preshape}, "
        f"{config.object.name}; {verdict}"
    )
    path = draw_snapshots(Path(run_dir) / "snapshots.png", scene, frames, title)
    return str(path)


def _outcome_dict(outcome: GraspOutcome) -> dict:
    T_world_object = outcome.T_world_object_at_hold
    return {
        "success": outcome.success,
        "failure_reason": outcome.failure_reason,
        "touching_fingers": outcome.touching_fingers,
        "n_contacts": len(outcome.contacts),
        "palm_contact": outcome.palm_contact,
        "corrections": outcome.corrections,
        "goals": outcome.goals,
        "held_after_lift": outcome.held_after_lift,
        "held_under_disturbance": outcome.held_under_disturbance,
        "object_rise": outcome.object_rise,
        "lift_motion": outcome.lift_motion.to_dict() if outcome.lift_motion else None,
        "disturbance": {d: m.to_dict() for d, m in outcome.disturbance.items()},
        "disturbance_skipped": outcome.disturbance_skipped,
        "fingers_after_lift": outcome.fingers_after_lift,
        "T_world_object_at_hold": T_world_object,
        "contacts_world": [c.to_dict() for c in outcome.contacts],
        "contacts_object": [c.in_object_frame(T_world_object).to_dict() for c in outcome.contacts],
    }


def _quality(contacts_object, obj) -> dict | None:
    """Ferrari-Canny L1 quality of contacts given in the object frame (None without
    contacts): the object's static friction, torques about its centroid over its half
    largest dimension (docs/method.md, "Grasp quality")."""
    if not contacts_object:
        return None
    try:
        quality = grasp_quality(
            [c.p for c in contacts_object],
            [-np.asarray(c.n) for c in contacts_object],  # contact normals point out
            obj.static_friction,
            torque_length=obj.largest_dimension / 2,
        )
    except GraspframeError as exc:  # e.g. a measured contacts file without normals
        return {"error": str(exc)}
    return quality.to_dict()


def _score(
    robot_contacts: list[Contact],
    reference: HumanReference,
    hand: HandDescription,
    human: HandDescription,
) -> dict:
    """Virtual fingers of robot and human from their object-frame contacts, compared."""
    score: dict = {
        "human_source": reference.source,
        "human_touching_fingers": reference.touching_fingers,
        # The simulated human grasp's own held test; None for measured contacts.
        "human_held_test": None if reference.held is None else reference.held.to_dict(),
    }
    try:
        robot_vf = virtual_fingers_from_contacts(robot_contacts)
        human_vf = virtual_fingers_from_contacts(reference.contacts)
        comparison = compare(
            robot_vf,
            human_vf,
            robot_real_fingers=list(hand.finger_names),
            human_real_fingers=list(human.finger_names),
        )
    except GraspframeError as exc:
        score["error"] = str(exc)
        return score
    score.update(
        robot=_with_contacts(robot_vf.to_dict(), robot_contacts),
        human=_with_contacts(human_vf.to_dict(), list(reference.contacts)),
        comparison=comparison.to_dict(),
    )
    # Name the real fingers on each side of every matched pair.
    for pair in score["comparison"]["pairs"]:
        pair["robot_members"] = score["robot"]["virtual_fingers"][pair["robot_index"]]["members"]
        pair["human_members"] = score["human"]["virtual_fingers"][pair["human_index"]]["members"]
    return score


def _with_contacts(grasp: dict, contacts_object) -> dict:
    """The virtual-finger dict with each virtual finger's contacts (object frame: p [m],
    n, f [N]) listed under it, taken from the real fingers it is made of."""
    for vf in grasp["virtual_fingers"]:
        members = set(vf["members"])
        vf["contacts"] = [c.to_dict() for c in contacts_object if c.real_finger in members]
    return grasp
