"""Contract checks for plugins: each returns the problems found, in plain words.

An empty list means the plugin honours the contract. `graspframe.testing` turns these
into assertions and pytest tests; keep the messages readable by a plugin author.
"""

from __future__ import annotations

import math
import re

import numpy as np

from graspframe.errors import GraspframeError
from graspframe.grasps import PALM, HumanGrasp
from graspframe.hal.classifier import Classifier, HumanGraspEstimate
from graspframe.hal.descriptions import ArmDescription, DriveGains, HandDescription, JointSpec
from graspframe.robot_model import summarize_urdf

NAME_PATTERN = re.compile(r"^[a-z][a-z0-9_]*$")
# URDF limits are written with limited precision; a description derived from the same
# numbers in degrees may differ in the last digits.
LIMIT_TOLERANCE = 1e-4  # [rad]
MAX_DELTA = 0.5  # [m] a palm-to-fingertip distance beyond this is surely a unit mistake


def _name_problems(kind: str, name: str) -> list[str]:
    if NAME_PATTERN.match(name or ""):
        return []
    return [
        f"{kind} name {name!r} must be lowercase letters, digits and '_', starting with a letter"
    ]


def _joint_spec_problems(joint: JointSpec, need_motion_limits: bool) -> list[str]:
    problems = []
    if not (math.isfinite(joint.lower) and math.isfinite(joint.upper)):
        problems.append(f"joint {joint.name!r} has an infinite position limit")
    elif joint.lower >= joint.upper:
        problems.append(
            f"joint {joint.name!r} lower limit {joint.lower:.4f} is not below its upper "
            f"limit {joint.upper:.4f}"
        )
    if not joint.max_velocity > 0 or not math.isfinite(joint.max_velocity):
        problems.append(f"joint {joint.name!r} needs a finite velocity limit > 0")
    if not joint.max_effort > 0:
        problems.append(f"joint {joint.name!r} needs an effort limit > 0")
    if need_motion_limits:
        for label, value in (("acceleration", joint.max_acceleration), ("jerk", joint.max_jerk)):
            if not (value > 0 and math.isfinite(value)):
                problems.append(f"joint {joint.name!r} needs a finite {label} limit > 0")
    return problems


def _drive_problems(drive: DriveGains) -> list[str]:
    if drive.stiffness > 0 and drive.damping >= 0 and drive.force_limit > 0:
        return []
    return ["drive gains need stiffness > 0, damping >= 0 and force_limit > 0"]


def _model_problems(
    model_path, joints: tuple[JointSpec, ...], links: list[tuple[str, str]]
) -> list[str]:
    """Joints and links against the URDF. links: (role, link name) pairs."""
    try:
        urdf = summarize_urdf(str(model_path))
    except GraspframeError as exc:
        return [str(exc)]
    problems = []
    for joint in joints:
        found = urdf.joints.get(joint.name)
        if found is None:
            problems.append(
                f"joint {joint.name!r} is not a movable joint of the model "
                f"{model_path.name}; it has: {', '.join(sorted(urdf.joints))}"
            )
            continue
        if (
            abs(found.lower - joint.lower) > LIMIT_TOLERANCE
            or abs(found.upper - joint.upper) > LIMIT_TOLERANCE
        ):
            problems.append(
                f"joint {joint.name!r} limits [{joint.lower:.4f}, {joint.upper:.4f}] differ "
                f"from the model's [{found.lower:.4f}, {found.upper:.4f}]"
            )
    for role, link in links:
        if link not in urdf.links:
            problems.append(f"{role} {link!r} is not a link of the model {model_path.name}")
    return problems


def hand_problems(hand: HandDescription) -> list[str]:
    """Everything wrong with a hand description, in plain words."""
    problems = _name_problems("hand", hand.name)
    if not hand.joints:
        problems.append("the hand declares no joints")
    names = [j.name for j in hand.joints]
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        problems.append(f"joints declared twice: {', '.join(duplicates)}")
    for joint in hand.joints:
        problems += _joint_spec_problems(joint, need_motion_limits=False)
    problems += _drive_problems(hand.drive)

    # Real fingers: a palm, no empty finger, no link in two fingers.
    if PALM not in hand.real_fingers:
        problems.append(
            f"real fingers must include {PALM!r}; found: {', '.join(hand.real_fingers)}"
        )
    seen: dict[str, str] = {}
    for finger, links in hand.real_fingers.items():
        if not links:
            problems.append(f"real finger {finger!r} has no links")
        for link in links:
            if link in seen:
                problems.append(f"link {link!r} is in real fingers {seen[link]!r} and {finger!r}")
            seen[link] = finger
    if hand.palm_sensor_link not in hand.real_fingers.get(PALM, ()):
        problems.append(f"palm sensor link {hand.palm_sensor_link!r} is not a link of the palm")

    # Couplings name known joints.
    known_joints = set(names)
    for c in hand.couplings:
        if c.leader not in known_joints:
            problems.append(f"coupling of {c.follower!r} follows unknown joint {c.leader!r}")

    # Preshapes within limits, over known joints.
    limits = {j.name: j for j in hand.joints}
    for preshape in hand.preshapes.values():
        for label, q in (("open", preshape.open_q), ("closed", preshape.closed_q)):
            for joint_name, value in q.items():
                spec = limits.get(joint_name)
                if spec is None:
                    problems.append(
                        f"preshape {preshape.name!r} ({label}) sets unknown joint {joint_name!r}"
                    )
                elif not spec.contains(value, tol=LIMIT_TOLERANCE):
                    problems.append(
                        f"preshape {preshape.name!r} ({label}) puts {joint_name!r} at "
                        f"{value:.4f} rad, outside [{spec.lower:.4f}, {spec.upper:.4f}]"
                    )
        if not 0.0 <= preshape.delta <= MAX_DELTA:
            problems.append(
                f"preshape {preshape.name!r} palm-to-fingertip distance {preshape.delta} m is "
                f"outside 0..{MAX_DELTA} m (is it in metres?)"
            )

    # Mapping table: every human grasp, each onto a defined preshape.
    missing = [g.value for g in HumanGrasp if g not in hand.grasp_map]
    if missing:
        problems.append(f"mapping table has no entry for: {', '.join(missing)}")
    for grasp, preshape_name in hand.grasp_map.items():
        if preshape_name not in hand.preshapes:
            problems.append(
                f"mapping table sends {grasp.value!r} to undefined preshape {preshape_name!r}"
            )

    links = [("root link", hand.root_link), ("palm frame", hand.palm_frame)]
    links += [
        (f"link of real finger {f!r}", link) for f, ls in hand.real_fingers.items() for link in ls
    ]
    problems += _model_problems(hand.model_path, hand.joints, links)
    return problems


def arm_problems(arm: ArmDescription) -> list[str]:
    """Everything wrong with an arm description, in plain words."""
    problems = _name_problems("arm", arm.name)
    if not arm.joints:
        problems.append("the arm declares no joints")
    for joint in arm.joints:
        problems += _joint_spec_problems(joint, need_motion_limits=True)
    problems += _drive_problems(arm.drive)
    if len(arm.home_q) != len(arm.joints):
        problems.append(f"home_q has {len(arm.home_q)} values for {len(arm.joints)} joints")
    else:
        for joint, q in zip(arm.joints, arm.home_q, strict=True):
            if not joint.contains(q):
                problems.append(f"home_q puts {joint.name!r} at {q:.4f} rad, outside its limits")
    links = [("base link", arm.base_link), ("flange link", arm.flange_link)]
    problems += _model_problems(arm.model_path, arm.joints, links)
    return problems


def classifier_problems(classifier_cls: type[Classifier]) -> list[str]:
    """A classifier must build with no arguments and refuse images it cannot use."""
    problems = _name_problems("classifier", getattr(classifier_cls, "name", ""))
    try:
        classifier = classifier_cls()
    except Exception as exc:
        return [*problems, f"cannot be built with no arguments: {type(exc).__name__}: {exc}"]
    not_images = {
        "an empty array": np.zeros((0, 0, 3), np.uint8),
        "a float image": np.zeros((64, 64, 3), np.float32),
        "a 1-D array": np.zeros(10, np.uint8),
    }
    handless = {"a uniform grey image": np.full((120, 160, 3), 128, np.uint8)}
    for label, image in {**not_images, **handless}.items():
        try:
            estimate = classifier.classify(image)
        except GraspframeError:
            continue
        except Exception as exc:
            problems.append(
                f"{label} raised {type(exc).__name__} instead of a GraspframeError: {exc}"
            )
            continue
        problems.append(f"{label} gave an estimate ({estimate.grasp.value}) instead of an error")
    return problems


def estimate_problems(estimate: HumanGraspEstimate) -> list[str]:
    """A classifier's estimate must be well formed."""
    problems = []
    if not isinstance(estimate.grasp, HumanGrasp):
        problems.append(f"grasp {estimate.grasp!r} is not a HumanGrasp")
    if not 0.0 <= estimate.confidence <= 1.0:
        problems.append(f"confidence {estimate.confidence} is outside [0, 1]")
    R = np.asarray(estimate.R_cam_hand, dtype=float)
    if R.shape != (3, 3) or not np.allclose(R.T @ R, np.eye(3), atol=1e-6):
        problems.append("R_cam_hand is not a 3x3 rotation matrix")
    return problems
