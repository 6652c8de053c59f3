"""Run events: what every stage of a run tells its observers.

This module is the catalogue of run events: every kind a run emits is declared here once,
as an `EventKind` with its payload fields, their units and frames. Emitters pass the
declaration (`emit(EXECUTE_CORRECTION, index=1, ...)`), observers compare `event.kind`
with its `name`. docs/hooks.md lists the same kinds and fields (a test checks it).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from graspframe.common.errors import GraspframeError

if TYPE_CHECKING:
    from graspframe.hal.descriptions import ArmDescription, HandDescription
    from graspframe.hal.objects import ObjectDescription


@dataclass(frozen=True)
class RunInfo:
    """Identity of a run: its id, output directory, the parameters it was started with,
    and the descriptions of what it runs, so observers need no name lookups.

    hand: the robot hand. arm: the arm the hand is mounted on (None when the hand rides
    the floating base). object: the object to grasp. Each is None when the run was started
    without it (a RunInfo made by hand).
    """

    run_id: str
    out_dir: str
    params: dict[str, Any] = field(default_factory=dict)
    hand: HandDescription | None = None
    arm: ArmDescription | None = None
    object: ObjectDescription | None = None


@dataclass(frozen=True)
class RunEvent:
    """One thing that happened during a run.

    kind: the dotted name of its `EventKind`, e.g. "classify.done", "execute.correction".
    sim_time: simulation time [s] when it happened (None for events outside simulation).
    data: event payload, the fields its `EventKind` declares; arrays are numpy arrays,
        poses 4x4 `T_a_b` matrices.
    """

    kind: str
    sim_time: float | None = None
    data: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class PayloadField:
    """One payload field of an event kind: its name and what it holds (unit, frame).
    optional: the field is left out in some events of the kind (`meaning` says when)."""

    name: str
    meaning: str
    optional: bool = False


@dataclass(frozen=True)
class EventKind:
    """A kind of run event: its dotted name, when it is emitted, its payload fields.

    observer_only: the event goes to the observers only, not into result.json's "events"
    (per-cycle samples, images and other bulky data).
    """

    name: str
    when: str
    fields: tuple[PayloadField, ...]
    observer_only: bool = False

    @property
    def field_names(self) -> tuple[str, ...]:
        """The payload field names, in declaration order."""
        return tuple(f.name for f in self.fields)

    def check(self, data: Mapping[str, Any]) -> None:
        """Raise GraspframeError when `data` holds an undeclared field or lacks a
        required one."""
        undeclared = sorted(set(data) - set(self.field_names))
        missing = [f.name for f in self.fields if not f.optional and f.name not in data]
        if undeclared or missing:
            raise GraspframeError(
                f"event {self.name}: undeclared payload fields {undeclared}, missing {missing}; "
                "the payload must match its declaration in graspframe/plugin_system/events.py"
            )


CLASSIFY_DONE = EventKind(
    "classify.done",
    "The classifier has estimated the human grasp in the image (runs from an image only).",
    (
        PayloadField("classifier", "name of the classifier"),
        PayloadField("grasp", "the human grasp recognised (a `HumanGrasp` value)"),
        PayloadField("confidence", "[0, 1] the classifier's confidence"),
        PayloadField("R_camera_palm", "3x3 rotation of the human palm frame in the camera frame"),
        PayloadField("p_camera_palm", "[m] human palm position in the camera frame, or None"),
        PayloadField("neighbours", "nearest database views: list of {view_id, grasp, distance}"),
        PayloadField("T_object_palm", "4x4 pose of the human palm in the object frame"),
    ),
)
CLASSIFY_IMAGES = EventKind(
    "classify.images",
    "Right after classify.done: the image the classifier saw and its pictures of its work.",
    (
        PayloadField("image_bgr", "HxWx3 uint8 input image, BGR"),
        PayloadField(
            "pictures",
            "the classifier's pictures of its work, a tuple of `ClassifierPicture` (name, kind "
            '"mask" or "image", pixels), e.g. its hand mask; empty when it shows none',
        ),
    ),
    observer_only=True,
)
PLAN_DONE = EventKind(
    "plan.done",
    "The grasp is planned and its path checked (world frame of the robot's belief).",
    (
        PayloadField("hand", "name of the robot hand"),
        PayloadField("grasp", "the human grasp copied (a `HumanGrasp` value)"),
        PayloadField("preshape", "name of the hand preshape"),
        PayloadField("volar", "whether the grasp is volar (the palm touches the object)"),
        PayloadField("approach", '"side" or "top"'),
        PayloadField("a_world", "unit approach direction, world frame"),
        PayloadField("T_object_human_palm", "4x4 human palm pose copied, object frame"),
        PayloadField("T_object_palm", "4x4 robot palm pose at the goal, object frame"),
        PayloadField("p_palm_object", "[m] the object's centroid in the palm frame at the goal"),
        PayloadField("T_world_object_est", "4x4 object pose the robot believes"),
        PayloadField("T_world_palm_goal", "4x4 palm goal: where it touches or stops"),
        PayloadField("T_world_palm_pre", "4x4 palm pose at the start of the approach"),
        PayloadField("T_world_palm_via", "4x4 palm pose reached first, before the approach"),
        PayloadField("standoff", "[m] height of the object's centroid above the palm"),
        PayloadField("table_raise", "[m] goal raised to keep the hand off the table"),
        PayloadField("min_goal_height", "[m] lowest world height of the palm origin"),
        PayloadField(
            "variant", "the variant tried: {yaw_deg, raise_along_axis [m], via_rise [m], mounting}"
        ),
        PayloadField("R_object_symmetry", "3x3 rotation of the object frame the variant used"),
        PayloadField("volar_gap", "[m] how far the palm backs off the object before closing"),
        PayloadField("lowest_link", "the hand link whose lowest point set min_goal_height"),
        PayloadField("lowest_below_palm", "[m] how far below the palm origin it reaches"),
        PayloadField(
            "reach", "how the fingers were kept on the object the raise lifted them off, or ''"
        ),
        PayloadField(
            "fingers_on_object", "the real fingers the closing brings onto the object (no physics)"
        ),
        PayloadField("fingers_without_table", "... and those it would with no table in the way"),
        PayloadField("open_inside_object", "hand links inside the object, open, at the goal"),
        PayloadField("lowest_touch_height", "[m] the lowest finger touch above the centroid"),
        PayloadField("variants_refused", "the variants refused before this one, with reasons"),
    ),
)
WORLD_BUILT = EventKind(
    "world.built",
    "The backend has built the world; from here on events carry the simulation time.",
    (
        PayloadField("hand", "name of the robot hand"),
        PayloadField("arm", "name of the arm (the floating base on the floating mount)"),
        PayloadField("arm_joint_names", "the arm's joint names, in q_arm order"),
        PayloadField("object", "name of the object"),
        PayloadField("model", "the model of the hand on its arm (a UrdfModel)"),
        PayloadField("T_world_arm_base", "4x4 pose of the arm base"),
        PayloadField("T_world_object", "4x4 true object pose"),
        PayloadField("T_world_object_est", "4x4 object pose the robot believes"),
        PayloadField("table_height", "[m] world height of the table top"),
    ),
)
MOTION_CYCLE = EventKind(
    "motion.cycle",
    "Every control cycle: the arm moving, or holding still (the hand closing, the hold, the "
    "held test's waits and pushes).",
    (
        PayloadField(
            "q_arm",
            "arm joint positions in arm_joint_names order [rad] ([m] for the floating "
            "base's x, y, z)",
        ),
        PayloadField("q_hand", "[rad] hand joint positions by joint name"),
        PayloadField("T_world_palm", "4x4 palm pose"),
        PayloadField("T_world_object", "4x4 true object pose"),
        PayloadField("palm_touched", "whether a palm link touches the object"),
        PayloadField("distance_to_goal", "[m] from the palm origin to the planned goal"),
    ),
    observer_only=True,
)
EXECUTE_PRESHAPE = EventKind(
    "execute.preshape",
    "The hand opens in its preshape as the arm starts to move.",
    (PayloadField("preshape", "name of the hand preshape"),),
)
EXECUTE_PRE_APPROACH = EventKind(
    "execute.pre_approach",
    "The palm has reached the start of the approach.",
    (
        PayloadField("duration", "[s] of the move there"),
        PayloadField("T_world_palm", "4x4 palm pose reached"),
    ),
)
EXECUTE_APPROACH = EventKind(
    "execute.approach",
    "An approach along the approach direction has ended (one per volar attempt).",
    (
        PayloadField("travel", "[m] distance the palm moved"),
        PayloadField("stopped", "whether a contact stopped it"),
        PayloadField("cycles", "control cycles it took"),
    ),
)
EXECUTE_NO_CONTACT = EventKind(
    "execute.no_contact",
    "A volar approach went past its goal without touching the object.",
    (PayloadField("goal", "[m] palm goal position of that approach, world frame"),),
)
EXECUTE_FIRST_CONTACT = EventKind(
    "execute.first_contact",
    "A volar approach stopped at its first contact.",
    (
        PayloadField("link", "hand link touching"),
        PayloadField("real_finger", "real finger of that link"),
        PayloadField("p_world", "[m] contact position, world frame"),
        PayloadField("on_palm", "whether the palm touches"),
    ),
)
EXECUTE_CORRECTIONS_EXHAUSTED = EventKind(
    "execute.corrections_exhausted",
    "The volar goal corrections ran out; the hand closes where it stands.",
    (PayloadField("corrections", "goal corrections made"),),
)
EXECUTE_SERVO = EventKind(
    "execute.servo",
    "The servo strategy measured the object with the depth camera and corrected the hand.",
    (
        PayloadField("stage", '"start", "via", "pre-approach" or "standoff"'),
        PayloadField("step", "1 for the first measurement of the stage, then 2, ..."),
        PayloadField(
            "fit",
            "the model fit: p_world_object [m], shift_mm from the believed position, "
            "points, inlier_fraction, rms_mm, accepted, reason (why not)",
        ),
        PayloadField("correction_mm", "[mm] the palm's move (x, y), world frame; 0 for none"),
        PayloadField(
            "skipped",
            "why an accepted correction was not made (at the standoff: larger than the "
            "sideways move allowed there); absent when it was made or not needed",
            optional=True,
        ),
    ),
)
EXECUTE_DEPTH_IMAGE = EventKind(
    "execute.depth_image",
    "The depth camera's image behind an execute.servo event (the robot filtered out).",
    (
        PayloadField("stage", '"start", "via", "pre-approach" or "standoff"'),
        PayloadField("step", "the execute.servo step it was measured for"),
        PayloadField("depth_m", "H x W depth along the optical axis [m], NaN: no return"),
        PayloadField("intrinsics", "fx, fy, cx, cy [px], width, height [px]"),
        PayloadField("T_world_camera", "4x4 camera pose (OpenCV axes: z along the view)"),
        PayloadField("p_world_fitted", "[m] the fitted object position"),
    ),
    observer_only=True,
)
EXECUTE_CORRECTION = EventKind(
    "execute.correction",
    "The volar goal moved: towards a finger contact, or to centre the palm contact.",
    (
        PayloadField("index", "1 for the first correction, then 2, ..."),
        PayloadField("reason", '"finger first" or "palm off centre"'),
        PayloadField("alpha", "weight of the contact point in the next correction, or None"),
        PayloadField("p_contact", "[m] the first contact's position, world frame"),
        PayloadField("goal_before", "[m] palm goal position before, world frame"),
        PayloadField("goal_after", "[m] palm goal position after, world frame"),
    ),
)
EXECUTE_BACK_OFF = EventKind(
    "execute.back_off",
    "The palm backed off the object it found, before closing.",
    (
        PayloadField("gap", "[m] asked for"),
        PayloadField("travel", "[m] moved along the approach direction (negative: back)"),
    ),
)
EXECUTE_CLOSED = EventKind(
    "execute.closed",
    "The hand has closed (its joints settled or the time limit passed).",
    (
        PayloadField("duration", "[s] of the closing"),
        PayloadField("q", "[rad] hand joint positions by joint name"),
    ),
)
EXECUTE_HOLD = EventKind(
    "execute.hold",
    "The hold time after closing has passed.",
    (
        PayloadField("fingers", "real fingers touching the object"),
        PayloadField("n_contacts", "number of contacts"),
        PayloadField("contacts", "the `Contact`s, world frame"),
    ),
)
EXECUTE_LIFT = EventKind(
    "execute.lift",
    "The lift has ended.",
    (
        PayloadField("object_rise", "[m] object height gained"),
        PayloadField("held", "whether the object was held in the lift"),
        PayloadField("fingers", "real fingers touching after the lift"),
        PayloadField("shift_mm", "[mm] largest object shift in the palm frame from the hold"),
        PayloadField("turn_deg", "[deg] largest object turn in the palm frame from the hold"),
    ),
)
EXECUTE_DISTURBANCE = EventKind(
    "execute.disturbance",
    "The disturbance test has ended, or the backend could not push the object.",
    (
        PayloadField("force", "[N] push along each world axis (absent when skipped)", True),
        PayloadField("held", "whether the object stayed in the hand (absent when skipped)", True),
        PayloadField(
            "motion",
            'per direction ("+x", ...), {shift_mm, turn_deg} (absent when skipped)',
            True,
        ),
        PayloadField("skipped", "why the test did not run (present only then)", True),
    ),
)
EXECUTE_SNAPSHOT = EventKind(
    "execute.snapshot",
    "At the end of the approach or the first contact, at the hold and after the lift.",
    (
        PayloadField("label", 'the moment, e.g. "first contact", "hold", "after lift"'),
        PayloadField("q_arm", "arm joint positions, as in motion.cycle (None without an arm)"),
        PayloadField("q_hand", "[rad] hand joint positions by joint name"),
        PayloadField("T_world_palm", "4x4 palm pose"),
        PayloadField("T_world_object", "4x4 true object pose"),
        PayloadField("contacts", "the `Contact`s, world frame"),
    ),
)
EXECUTE_ABORTED = EventKind(
    "execute.aborted",
    "The arm could not carry the plan out; the grasp stops where it stands.",
    (PayloadField("reason", "the motion error, in words"),),
)
EXECUTE_JOINT_LIMIT = EventKind(
    "execute.joint_limit",
    "A joint has passed its model limit by more than the tolerance (2 deg, 2 mm), the "
    "first time in the run; result.json's joint_limits keeps its largest excess.",
    (
        PayloadField("joint", "the joint's name"),
        PayloadField("position", "[rad] ([m] for a prismatic joint) its measured position"),
        PayloadField("lower", "[rad] ([m]) its lower limit in the model"),
        PayloadField("upper", "[rad] ([m]) its upper limit in the model"),
        PayloadField("excess", "[rad] ([m]) past the nearer limit"),
    ),
)
SCORE_DONE = EventKind(
    "score.done",
    "The robot grasp is scored against the human reference.",
    (
        PayloadField("score", "the score of result.json (virtual fingers, comparison, quality)"),
        PayloadField("human_contacts", "the human reference's `Contact`s, object frame"),
        PayloadField("robot_contacts_object", "the robot's `Contact`s at the hold, object frame"),
    ),
    observer_only=True,
)

# In the order a run emits them.
EVENT_KINDS: tuple[EventKind, ...] = (
    CLASSIFY_DONE,
    CLASSIFY_IMAGES,
    PLAN_DONE,
    WORLD_BUILT,
    MOTION_CYCLE,
    EXECUTE_PRESHAPE,
    EXECUTE_PRE_APPROACH,
    EXECUTE_APPROACH,
    EXECUTE_NO_CONTACT,
    EXECUTE_FIRST_CONTACT,
    EXECUTE_CORRECTIONS_EXHAUSTED,
    EXECUTE_CORRECTION,
    EXECUTE_DEPTH_IMAGE,
    EXECUTE_SERVO,
    EXECUTE_BACK_OFF,
    EXECUTE_CLOSED,
    EXECUTE_HOLD,
    EXECUTE_LIFT,
    EXECUTE_DISTURBANCE,
    EXECUTE_SNAPSHOT,
    EXECUTE_ABORTED,
    EXECUTE_JOINT_LIMIT,
    SCORE_DONE,
)
