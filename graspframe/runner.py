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
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from graspframe.errors import GraspframeError, InputError
from graspframe.events import RunEvent, RunInfo
from graspframe.grasps import HumanGrasp
from graspframe.hal.drivers import WorldConfig
from graspframe.metrics.virtual_fingers import compare, virtual_fingers_from_contacts
from graspframe.motion.arm_motion import ArmMotion
from graspframe.registry import Registry, default_registry
from graspframe.results import new_run_dir, versions, write_json
from graspframe.strategy.executor import ExecutorParams, GraspOutcome, execute_plan
from graspframe.strategy.human_reference import (
    HumanReference,
    human_reference,
    load_reference_file,
)
from graspframe.strategy.planner import PlannerParams, plan_grasp
from graspframe.strategy.reference_poses import reference_placement
from graspframe.transforms import make_T

log = logging.getLogger(__name__)

SCENE_OBJECT_XY = (0.55, 0.20)  # [m]
TABLE_HEIGHT = 0.0  # [m]
HUMAN_HAND = "human"
MAX_OBJECT_ERROR = 0.5  # [m] larger injected errors are surely a unit mistake


@dataclass(frozen=True)
class RunRequest:
    """What to run. object_error: [m] (dx, dy) added to the object position the robot
    believes (the object itself stays put). human_contacts: a measured-contacts file
    replacing the simulated human reference."""

    hand: str
    grasp: HumanGrasp
    arm: str = "kuka"
    object: str | None = None
    object_error: tuple[float, float] = (0.0, 0.0)
    seed: int = 0
    backend: str = "sapien"
    out_root: str = "runs"
    human_contacts: str | None = None

    def command(self) -> str:
        """The command line that repeats this run."""
        parts = ["graspframe", "run", "--hand", self.hand, "--grasp", self.grasp.value]
        parts += ["--arm", self.arm, "--seed", str(self.seed)]
        if self.object:
            parts += ["--object", self.object]
        if any(self.object_error):
            dx, dy = (1000.0 * v for v in self.object_error)
            parts += ["--object-error-mm", f"{dx:g},{dy:g}"]
        if self.human_contacts:
            parts += ["--human-contacts", self.human_contacts]
        return " ".join(parts)


Progress = Callable[[str], None]


@dataclass
class _Recorder:
    """Collects events for result.json and forwards them to the observer plugins."""

    registry: Registry
    run: RunInfo
    events: list[dict] = field(default_factory=list)
    clock: Callable[[], float | None] = lambda: None

    def emit(self, kind: str, **data) -> None:
        event = RunEvent(kind, self.clock(), data)
        if not kind.startswith("motion."):  # per-cycle samples go to observers only
            self.events.append({"kind": kind, "sim_time": event.sim_time, **data})
        self.registry.notify_run_event(self.run, event)


def resolve(request: RunRequest, registry: Registry):
    """Look every name up first: unknown names fail before anything runs."""
    hand = registry.get_hand(request.hand)
    arm = registry.get_arm(request.arm)
    backend_cls = registry.get_backend(request.backend)
    obj = (
        registry.get_object(request.object)
        if request.object
        else registry.default_object_for(request.grasp)
    )
    if any(not np.isfinite(v) or abs(v) > MAX_OBJECT_ERROR for v in request.object_error):
        raise InputError(
            f"object error {request.object_error} m is not finite or above {MAX_OBJECT_ERROR} m"
        )
    return hand, arm, backend_cls, obj


def run_grasp(
    request: RunRequest, registry: Registry | None = None, progress: Progress | None = None
) -> dict:
    """Run one grasp and write runs/<id>/result.json; returns the result dictionary.

    A failure after the run folder exists is recorded (status "failed", the error) and
    re-raised; the result file is written in every case.
    """
    registry = registry or default_registry()
    progress = progress or (lambda message: None)
    hand, arm, backend_cls, obj = resolve(request, registry)
    human = registry.get_hand(HUMAN_HAND)
    reference_file = load_reference_file(request.human_contacts) if request.human_contacts else None

    run_dir = new_run_dir(request.out_root, f"{hand.name}-{request.grasp.value}")
    run = RunInfo(run_dir.name, str(run_dir), asdict(request))
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
        _execute(
            request, hand, arm, backend_cls, obj, human, reference_file, recorder, result, progress
        )
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
        write_json(result_path, result)
        registry.notify_run_finished(run, result)
    return result


def _execute(
    request, hand, arm, backend_cls, obj, human, reference_file, recorder, result, progress
):
    grasp = request.grasp
    # The human grasp: the reference placement of the human palm on this object.
    placement = reference_placement(obj, human.preshape_for(grasp))
    T_world_object = make_T(p=[*SCENE_OBJECT_XY, TABLE_HEIGHT + obj.half_height])
    T_world_object_est = T_world_object.copy()
    T_world_object_est[:2, 3] += request.object_error

    progress("planning")
    plan = plan_grasp(
        grasp,
        placement.T_object_palm,
        T_world_object_est,
        hand,
        p_hand_grasp=placement.p_palm_grasp,
        table_height=TABLE_HEIGHT,
        object_top_height=T_world_object_est[2, 3] + obj.half_height,
        params=PlannerParams(),
    )
    result["plan"] = plan.to_dict()
    recorder.emit("plan.done", **plan.to_dict())

    progress("building the world")
    config = WorldConfig(
        hand=hand,
        arm=arm,
        object=obj,
        T_world_object=T_world_object,
        table_height=TABLE_HEIGHT,
        seed=request.seed,
    )
    with backend_cls().create_world(config) as world:
        recorder.clock = lambda: world.time

        def on_cycle(motion: ArmMotion) -> None:
            recorder.emit(
                "motion.cycle",
                q_arm=world.arm.joint_positions(),
                q_hand=world.hand.joint_positions(),
                T_world_palm=world.hand.T_world_palm(),
            )

        motion = ArmMotion(world, world.robot, config.T_world_arm_base, on_cycle=on_cycle)
        progress(f"executing the {plan.preshape} preshape ({plan.approach} approach)")
        outcome = execute_plan(plan, world, motion, hand, ExecutorParams(), emit=recorder.emit)
    result["outcome"] = _outcome_dict(outcome)

    progress("scoring against the human reference")
    reference = reference_file or human_reference(grasp, obj, human, backend_cls())
    result["score"] = _score(outcome, reference, hand, human)


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
        "object_rise": outcome.object_rise,
        "fingers_after_lift": outcome.fingers_after_lift,
        "T_world_object_at_hold": T_world_object,
        "contacts_world": [c.to_dict() for c in outcome.contacts],
        "contacts_object": [c.in_frame(T_world_object).to_dict() for c in outcome.contacts],
    }


def _score(outcome: GraspOutcome, reference: HumanReference, hand, human) -> dict:
    """Virtual fingers of robot and human, compared in the object frame."""
    score: dict = {
        "human_source": reference.source,
        "human_touching_fingers": reference.touching_fingers,
    }
    try:
        robot_vf = virtual_fingers_from_contacts(outcome.contacts, outcome.T_world_object_at_hold)
        human_vf = virtual_fingers_from_contacts(list(reference.contacts), np.eye(4))
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
        robot=robot_vf.to_dict(), human=human_vf.to_dict(), comparison=comparison.to_dict()
    )
    return score
