"""What each stage of a run hands to the next, and the run's result: typed values, and
the one place result.json is written from them.

The stages (graspframe/run/runner.py): the human grasp (`HumanGraspInput`: stated, or
classified from an image, `Classification`), the checked plan (`CheckedPlan`,
strategy/arm_path.py), the execution (`Execution`, strategy/execution.py: the outcome
with its held verdict, and the moments for pictures), the score against the human
reference (`Score`). `RunResult` holds them all, with what the run was asked, how it
ended and where its files are; `RunResult.to_json()` is result.json (format
RESULT_FORMAT), read back as plain JSON by the sweeps' tables and by users.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact
from graspframe.common.defaults import SCENE_OBJECT_XY, TABLE_HEIGHT
from graspframe.common.grasps import HumanGrasp
from graspframe.common.json_files import jsonable
from graspframe.hal.classifier import Neighbour
from graspframe.metrics.quality import GraspQuality
from graspframe.metrics.virtual_fingers import VirtualFingerComparison, VirtualFingerGrasp
from graspframe.motion.joint_limits import LimitExcess
from graspframe.strategy.arm_path import CheckedPlan
from graspframe.strategy.execution import Execution, GraspOutcome
from graspframe.strategy.held_check import HeldVerdict, InHandMotion

if TYPE_CHECKING:  # the runner imports this module; the servo only for its strategy
    from graspframe.perception.servo_step import ServoStep
    from graspframe.run.request import RunRequest

RESULT_FORMAT = "graspframe.result/2"


@dataclass(frozen=True)
class Classification:
    """A classifier's answer for the run's image, and the human palm it places on the
    object (T_object_palm)."""

    classifier: str
    grasp: HumanGrasp
    confidence: float
    R_camera_palm: NDArray[np.float64]
    p_camera_palm: NDArray[np.float64] | None
    neighbours: tuple[Neighbour, ...]
    T_object_palm: NDArray[np.float64]

    def to_json(self) -> dict[str, Any]:
        return {
            "classifier": self.classifier,
            "grasp": self.grasp.value,
            "confidence": self.confidence,
            "R_camera_palm": self.R_camera_palm,
            "p_camera_palm": self.p_camera_palm,
            "neighbours": [
                {"view_id": n.view_id, "grasp": n.grasp.value, "distance": n.distance}
                for n in self.neighbours
            ],
            "T_object_palm": self.T_object_palm,
        }


@dataclass(frozen=True)
class HumanGraspInput:
    """The human grasp the robot copies: which grasp, the human palm in the object frame
    (T_object_palm) and where the object is (T_world_object); `classification` when it
    came from an image."""

    grasp: HumanGrasp
    T_object_palm: NDArray[np.float64]
    T_world_object: NDArray[np.float64]
    classification: Classification | None = None


@dataclass(frozen=True)
class Quality:
    """Ferrari-Canny L1 grasp quality of a contact set (metrics/quality.py's numbers), or
    why it could not be computed."""

    measured: GraspQuality | None = None
    error: str | None = None

    def to_json(self) -> dict[str, Any] | None:
        if self.error is not None:
            return {"error": self.error}
        return None if self.measured is None else self.measured.to_dict()


@dataclass(frozen=True)
class Score:
    """The robot's grasp against the human reference.

    human_source: where the reference came from ("simulated", "cache" or a file);
    human_held: the simulated reference's own held test (None for measured contacts);
    robot_contacts, human_contacts: object frame; robot, human: their virtual fingers
    and `comparison` (None when they could not be scored: `error` says why);
    quality_robot, quality_human: grasp quality of each contact set;
    human_joint_limit_violations: the human reference's joints the simulator moved past
    their model limit (as in result.json's joint_limits).
    """

    human_source: str
    human_touching_fingers: tuple[str, ...]
    human_held: HeldVerdict | None
    robot_contacts: tuple[Contact, ...]
    human_contacts: tuple[Contact, ...]
    robot: VirtualFingerGrasp | None = None
    human: VirtualFingerGrasp | None = None
    comparison: VirtualFingerComparison | None = None
    error: str | None = None
    quality_robot: Quality = field(default_factory=Quality)
    quality_human: Quality = field(default_factory=Quality)
    human_joint_limit_violations: tuple[LimitExcess, ...] = ()

    def to_json(self) -> dict[str, Any]:
        data: dict[str, Any] = {
            "human_source": self.human_source,
            "human_touching_fingers": list(self.human_touching_fingers),
            "human_held_test": None if self.human_held is None else self.human_held.result_json(),
            "human_joint_limit_violations": [
                e.to_dict() for e in self.human_joint_limit_violations
            ],
        }
        if self.error is not None:
            data["error"] = self.error
        if self.robot is not None and self.human is not None and self.comparison is not None:
            robot = _with_contacts(self.robot.to_dict(), self.robot_contacts)
            human = _with_contacts(self.human.to_dict(), self.human_contacts)
            comparison = self.comparison.to_dict()
            # Name the real fingers on each side of every matched pair.
            for pair in comparison["pairs"]:
                pair["robot_members"] = robot["virtual_fingers"][pair["robot_index"]]["members"]
                pair["human_members"] = human["virtual_fingers"][pair["human_index"]]["members"]
            data.update(robot=robot, human=human, comparison=comparison)
        data["quality"] = {
            "robot": self.quality_robot.to_json(),
            "human": self.quality_human.to_json(),
        }
        return data


def _with_contacts(grasp: dict, contacts_object: Sequence[Contact]) -> dict:
    """The virtual-finger dict with each virtual finger's contacts (object frame: p [m],
    n, f [N]) listed under it, taken from the real fingers it is made of."""
    for vf in grasp["virtual_fingers"]:
        members = set(vf["members"])
        vf["contacts"] = [c.to_dict() for c in contacts_object if c.real_finger in members]
    return grasp


# result.json's names of the held verdict's fields where they differ; its failure is
# the outcome's failure_reason.
_VERDICT_NAMES = {"after_lift": "held_after_lift", "under_disturbance": "held_under_disturbance"}
_VERDICT_NOT_LISTED = ("failure",)


def outcome_json(outcome: GraspOutcome) -> dict[str, Any]:
    """result.json's "outcome": the grasp (every field of its `Grip`) and its held test
    (every field of its `HeldVerdict`, motions in the hand in [mm] and [deg]), with
    its contacts in the world and the object frame."""
    T_world_object = outcome.T_world_object_at_hold
    data: dict[str, Any] = {
        "success": outcome.success,
        "failure_reason": outcome.failure_reason,
        "touching_fingers": outcome.touching_fingers,
        "n_contacts": len(outcome.contacts),
    }
    data.update(jsonable(outcome.grip))
    verdict = outcome.verdict
    for item in fields(verdict):
        if item.name not in _VERDICT_NOT_LISTED:
            value = _with_motions_shown(getattr(verdict, item.name))
            data[_VERDICT_NAMES.get(item.name, item.name)] = value
    data["T_world_object_at_hold"] = T_world_object
    data["contacts_world"] = [c.to_dict() for c in outcome.contacts]
    data["contacts_object"] = [
        c.in_object_frame(T_world_object).to_dict() for c in outcome.contacts
    ]
    return data


def _with_motions_shown(value: Any) -> Any:
    """`value` with its motions in the hand as result.json shows them ([mm], [deg])."""
    if isinstance(value, InHandMotion):
        return value.to_dict()
    if isinstance(value, Mapping):
        return {key: _with_motions_shown(item) for key, item in value.items()}
    return value


@dataclass(frozen=True)
class ServoReport:
    """The servo strategy's measurements, in the order it made them, and servo.png."""

    steps: tuple[ServoStep, ...]
    picture: Path


@dataclass(frozen=True)
class StageOutputs:
    """What a run's stages produced, in the order they run (None: the stage was not
    reached): the human grasp, the checked plan, the execution, the servo's report,
    snapshots.png, the score and the human reference's picture. The one list of the
    stages: the runner fills it, `RunResult` carries it."""

    human: HumanGraspInput | None = None
    plan: CheckedPlan | None = None
    execution: Execution | None = None
    servo: ServoReport | None = None
    snapshots: Path | None = None
    score: Score | None = None
    human_reference_picture: Path | None = None

    def by_name(self) -> dict[str, Any]:
        """Each stage's output by its name (not converted, unlike dataclasses.asdict)."""
        return {f.name: getattr(self, f.name) for f in fields(StageOutputs)}


@dataclass(frozen=True, kw_only=True)
class RunResult(StageOutputs):
    """One run: what was asked, how it ended, what each stage produced (the fields of
    `StageOutputs`, None for the stages it did not reach) and where its files are.

    status: "running" (written at the start), "ok", "failed" (`error`, `traceback`) or
        "interrupted" (Ctrl-C or SIGTERM; `error` names which);
    artifacts: files the observers wrote, by name (e.g. "recording").
    """

    run_id: str
    request: RunRequest
    versions: Mapping[str, str]
    result_path: Path
    status: str = "running"
    error: str | None = None
    traceback: str | None = None
    wall_time: float | None = None
    events: tuple[dict, ...] = ()
    artifacts: Mapping[str, str] = field(default_factory=dict)

    @property
    def outcome(self) -> GraspOutcome | None:
        return None if self.execution is None else self.execution.outcome

    def to_json(self) -> dict[str, Any]:
        """result.json: the plain JSON form of the result (graspframe.common.json_files.jsonable
        turns its arrays and paths into JSON values)."""
        data: dict[str, Any] = {
            "format": RESULT_FORMAT,
            "run_id": self.run_id,
            "status": self.status,
            "request": asdict(self.request),
            "reproduce": self.request.command(),
            "seed": self.request.seed,
            "versions": dict(self.versions),
            "scene": {"object_xy": SCENE_OBJECT_XY, "table_height": TABLE_HEIGHT},
        }
        if self.human is not None and self.human.classification is not None:
            data["classification"] = self.human.classification.to_json()
        if self.plan is not None:
            data["plan"] = plan_json(self.plan)
        if self.execution is not None:
            data["outcome"] = outcome_json(self.execution.outcome)
            data["joint_limits"] = self.execution.joint_limits.to_json()
            data["snapshots"] = None if self.snapshots is None else str(self.snapshots)
        if self.score is not None:
            data["score"] = self.score.to_json()
        if self.human_reference_picture is not None:
            data["human_reference_picture"] = str(self.human_reference_picture)
        if self.servo is not None:
            steps = [step.to_json() for step in self.servo.steps]
            data["servo"] = {"steps": steps, "picture": str(self.servo.picture)}
        if self.error is not None:
            data["error"] = self.error
            data["traceback"] = self.traceback
        if self.wall_time is not None:
            data["wall_time"] = self.wall_time
        data["events"] = list(self.events)
        data["result_path"] = str(self.result_path)
        data.update(self.artifacts)
        return data


def plan_json(checked: CheckedPlan) -> dict[str, Any]:
    """result.json's "plan": the plan, with the variants refused before it."""
    return {**jsonable(checked.plan), "variants_refused": list(checked.refused)}
