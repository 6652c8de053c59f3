"""Contract checks for plugins: each returns the problems found, in plain words.

An empty list means the plugin honours the contract. `graspframe.testing` turns these
into assertions and pytest tests; keep the messages readable by a plugin author.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
from numpy.typing import NDArray

from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.common.transforms import R_from_rpy, make_T
from graspframe.hal.classifier import (
    PICTURE_KINDS,
    Classifier,
    ClassifierPicture,
    HumanGraspEstimate,
)
from graspframe.hal.descriptions import (
    ArmDescription,
    DriveGains,
    HandDescription,
    JointSpec,
    Mounting,
    joints_by_name,
)
from graspframe.hal.drivers import ArmDriver, Backend, World, WorldConfig
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.hal.objects import ObjectDescription
from graspframe.robot_models.model import CollisionModel, model_of, summarize_urdf

NAME_PATTERN = re.compile(r"^[a-z][a-z0-9_]*$")
# URDF limits are written with limited precision; a description derived from the same
# numbers in degrees may differ in the last digits.
LIMIT_TOLERANCE = 1e-4  # [rad]
MAX_DELTA = 0.5  # [m] a palm-to-fingertip distance beyond this is surely a unit mistake
# Probe points along the palm normal: in front of the palm surface must be free space,
# just behind it must be inside the palm body.
PALM_PROBE_OUT = 0.02  # [m]
PALM_PROBE_IN = 0.01  # [m]


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
    description: HandDescription | ArmDescription,
    joints: tuple[JointSpec, ...],
    links: list[tuple[str, str]],
) -> list[str]:
    """Joints and links against the model. links: (role, link name) pairs."""
    try:
        model = model_of(description)
        urdf = summarize_urdf(model)
    except GraspframeError as exc:
        return [str(exc)]
    problems = []
    for joint in joints:
        found = urdf.joints.get(joint.name)
        if found is None:
            problems.append(
                f"joint {joint.name!r} is not a movable joint of the model "
                f"{model.describe()}; it has: {', '.join(sorted(urdf.joints))}"
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
            problems.append(f"{role} {link!r} is not a link of the model {model.describe()}")
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

    # Mountings: named like plugins, each a `Mounting` (validated when built).
    for name, mounting in hand.mountings.items():
        problems += _name_problems("mounting", name)
        if not isinstance(mounting, Mounting):
            problems.append(f"mounting {name!r} is a {type(mounting).__name__}, not a Mounting")

    named_links = [("root link", hand.root_link), ("palm frame", hand.palm_frame)]
    named_links += [
        (f"link of real finger {f!r}", link) for f, ls in hand.real_fingers.items() for link in ls
    ]
    tip_problems, tips = _fingertip_problems(hand)
    problems += tip_problems
    named_links += [(f"fingertip frame of {finger!r}", frame) for finger, frame in tips.items()]
    problems += _model_problems(hand, hand.joints, named_links)
    # The palm direction needs only the model, its palm frame and palm links: check it
    # also when the joints are wrong, so that one run names every defect.
    if _model_has_links(hand, {hand.palm_frame, *hand.real_fingers.get(PALM, ())}):
        problems += palm_direction_problems(hand)
    return problems


def _fingertip_problems(hand: HandDescription) -> tuple[list[str], dict[str, str]]:
    """(problems, fingertip frames): the fingertip frames the hand names
    (`HandDescription.fingertip_frames`) must belong to its real fingers, not the palm."""
    tips = dict(hand.fingertip_frames)
    problems = [
        f"fingertip frame {frame!r} is given for {finger!r}, which is not a real finger "
        f"(real fingers: {', '.join(f for f in hand.real_fingers if f != PALM)})"
        for finger, frame in tips.items()
        if finger not in hand.real_fingers or finger == PALM
    ]
    return problems, tips


def _model_has_links(hand: HandDescription, links: set[str]) -> bool:
    """True when the model loads and has all these links."""
    try:
        return links <= summarize_urdf(model_of(hand)).links
    except GraspframeError:
        return False


def palm_direction_problems(hand: HandDescription) -> list[str]:
    """The palm frame's +z must point out of the palm: a point PALM_PROBE_OUT in front of
    the palm surface is in free space, a point PALM_PROBE_IN behind it is in a palm link."""
    try:
        model = CollisionModel(model_of(hand))
    except GraspframeError as exc:
        return [str(exc)]
    T_root_palm = model.T_root_frame(hand.palm_frame)
    origin, z_axis = T_root_palm[:3, 3], T_root_palm[:3, 2]
    in_front = model.links_containing(origin + PALM_PROBE_OUT * z_axis)
    behind = model.links_containing(origin - PALM_PROBE_IN * z_axis)
    palm_links = set(hand.real_fingers.get(PALM, ()))
    problems = []
    if in_front:
        problems.append(
            f"palm frame +z points into the hand: {PALM_PROBE_OUT * 100:g} cm along +z lies "
            f"inside {', '.join(in_front)} (+z must point out of the palm, towards the object)"
        )
    if not palm_links.intersection(behind):
        problems.append(
            f"palm frame is not on the palm surface: {PALM_PROBE_IN * 100:g} cm along -z is "
            "not inside a palm link (put the origin on the palm surface, +z outwards)"
        )
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
    problems += _model_problems(arm, arm.joints, links)
    return problems


def classifier_problems(classifier_cls: type[Classifier]) -> list[str]:
    """A classifier must build with no arguments and refuse images it cannot use."""
    problems = _name_problems("classifier", getattr(classifier_cls, "name", ""))
    try:
        classifier = classifier_cls()
    except Exception as exc:
        return [*problems, f"cannot be built with no arguments: {type(exc).__name__}: {exc}"]
    not_images: dict[str, NDArray[Any]] = {
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


def estimate_problems(
    estimate: HumanGraspEstimate, image_shape: tuple[int, ...] | None = None
) -> list[str]:
    """A classifier's estimate must be well formed; with the classified image's shape,
    its masks must be the image's size."""
    problems = []
    if not isinstance(estimate.grasp, HumanGrasp):
        problems.append(f"grasp {estimate.grasp!r} is not a HumanGrasp")
    if not 0.0 <= estimate.confidence <= 1.0:
        problems.append(f"confidence {estimate.confidence} is outside [0, 1]")
    R = np.asarray(estimate.R_camera_palm, dtype=float)
    if R.shape != (3, 3) or not np.allclose(R.T @ R, np.eye(3), atol=1e-6):
        problems.append("R_camera_palm is not a 3x3 rotation matrix")
    names = [picture.name for picture in estimate.pictures]
    if len(set(names)) != len(names):
        problems.append(f"picture names repeat: {names}")
    for picture in estimate.pictures:
        problems += _picture_problems(picture, image_shape)
    return problems


def _picture_problems(picture: ClassifierPicture, image_shape: tuple[int, ...] | None) -> list[str]:
    """A classifier's picture: a known kind, uint8 pixels of a mask's or an image's shape."""
    pixels = picture.pixels
    label = f"picture {picture.name!r}"
    if picture.kind not in PICTURE_KINDS:
        return [f"{label}: kind {picture.kind!r} is not one of {', '.join(PICTURE_KINDS)}"]
    if not isinstance(pixels, np.ndarray) or pixels.dtype != np.uint8:
        return [f"{label}: pixels are not a uint8 array"]
    if picture.kind == "mask":
        if pixels.ndim != 2:
            return [f"{label}: a mask is H x W, got shape {pixels.shape}"]
        if image_shape is not None and pixels.shape != tuple(image_shape[:2]):
            return [f"{label}: mask {pixels.shape} is not the image's size {image_shape[:2]}"]
    elif not (pixels.ndim == 2 or (pixels.ndim == 3 and pixels.shape[2] == 3)):
        return [f"{label}: an image is H x W or H x W x 3, got shape {pixels.shape}"]
    return []


BACKEND_TRACKING_TOL = np.radians(0.5)  # [rad] arm joints must hold home this closely
FREE_POSE_TOL = 1e-3  # [m] a free-floating hand must be placed this closely
MOUNTED_PALM_TOL = 1e-3  # [m] the palm must be where the mounted model puts it
# The backend contract mounts the hand turned on the flange and lifted off it, and the
# arm off the world origin, so that a backend ignoring the given mounting or base shows.
CONTRACT_T_FLANGE_HAND = make_T(R_from_rpy(0.0, 0.0, np.pi / 2), [0.0, 0.0, 0.01])
CONTRACT_T_WORLD_ARM_BASE = make_T(p=[-0.05, 0.02, 0.0])


def _mounted_palm_problems(
    world: World, arm_driver: ArmDriver, robot: MountedRobot, T_world_arm_base: NDArray[np.float64]
) -> list[str]:
    """The measured palm pose against the mounted model's forward kinematics at the
    measured joints."""
    model = CollisionModel(robot.model)
    q_hand = robot.hand.with_model_followers(world.hand.joint_positions())
    model.place(joints_by_name(robot.arm.joint_names, arm_driver.joint_positions(), q_hand))
    T_world_palm_model = T_world_arm_base @ model.T_root_frame(robot.hand.palm_frame)
    T_world_palm = np.asarray(world.hand.T_world_palm())
    error = float(np.linalg.norm(T_world_palm[:3, 3] - T_world_palm_model[:3, 3]))
    error_R = float(np.abs(T_world_palm[:3, :3] - T_world_palm_model[:3, :3]).max())
    if error > MOUNTED_PALM_TOL or error_R > MOUNTED_PALM_TOL:
        return [
            f"the palm is {error * 1000:.1f} mm from where the mounted model "
            f"({robot.model.name}, hand on the flange at config.robot.T_flange_hand, "
            "arm base at config.T_world_arm_base) puts it: load config.robot.model"
        ]
    return []


def backend_problems(
    backend_cls: type[Backend], hand: HandDescription, arm: ArmDescription, obj: ObjectDescription
) -> list[str]:
    """A backend must build worlds (mounted and free-floating) whose drivers behave, the
    mounted one from the model the core mounted (`WorldConfig.robot`)."""
    from graspframe.common.contacts import Contact, PalmSensorReading
    from graspframe.robot_models.mounting import mount

    problems = _name_problems("backend", getattr(backend_cls, "name", ""))
    try:
        backend = backend_cls()
    except Exception as exc:
        return [*problems, f"cannot be built with no arguments: {type(exc).__name__}: {exc}"]
    # The object 0.5 m in front of the arm, resting on the table (top at z = 0).
    T_world_object = obj.T_world_standing((0.5, 0.0))
    robot = mount(arm, hand, CONTRACT_T_FLANGE_HAND)
    config = WorldConfig(
        hand=hand,
        object=obj,
        robot=robot,
        T_world_arm_base=CONTRACT_T_WORLD_ARM_BASE,
        T_world_object=T_world_object,
    )
    try:
        world = backend.create_world(config)
    except Exception as exc:
        return [*problems, f"create_world failed: {type(exc).__name__}: {exc}"]
    with world:
        arm_driver = world.arm
        if arm_driver is None:
            return [*problems, "a world with a mounted robot has no arm driver (World.arm)"]
        if tuple(arm_driver.joint_names) != arm.joint_names:
            problems.append("the arm driver's joints differ from the arm description's")
        if set(world.hand.joint_names) != set(hand.joint_names):
            problems.append("the hand driver's joints differ from the hand description's")
        t0 = world.time
        world.step(10)
        if abs(world.time - t0 - 10 * world.timestep) > 1e-9:
            problems.append("time does not advance by timestep per step")
        arm_driver.set_joint_targets(np.asarray(arm.home_q))
        world.step(max(1, round(0.5 / world.timestep)))
        error = np.abs(arm_driver.joint_positions() - np.asarray(arm.home_q)).max()
        if error > BACKEND_TRACKING_TOL:
            problems.append(
                f"arm does not hold its home configuration: {np.degrees(error):.2f} deg off"
            )
        try:
            arm_driver.set_joint_targets(np.zeros(arm.dof + 1))
            problems.append("arm targets of the wrong length were accepted")
        except GraspframeError:
            pass
        contacts = world.hand.contacts()
        if not isinstance(contacts, list) or not all(isinstance(c, Contact) for c in contacts):
            problems.append("contacts() must return a list of Contact")
        if not isinstance(world.hand.palm_sensor(), PalmSensorReading):
            problems.append("palm_sensor() must return a PalmSensorReading")
        T_world_palm = np.asarray(world.hand.T_world_palm())
        if T_world_palm.shape != (4, 4):
            problems.append("T_world_palm() must return a 4x4 pose")
        else:
            problems += _mounted_palm_problems(world, arm_driver, robot, CONTRACT_T_WORLD_ARM_BASE)
        if (
            world.object is None
            or np.linalg.norm(world.object.T_world_object()[:3, 3] - T_world_object[:3, 3]) > 0.01
        ):
            problems.append("the object is not where the configuration put it")

    free_config = WorldConfig(hand=hand, object=None)
    try:
        with backend.create_world(free_config) as free_world:
            T_target = make_T(p=[0.1, -0.2, 0.5])
            free_world.hand.set_free_pose(T_target)
            free_world.step(1)
            placed = free_world.hand.T_world_palm()[:3, 3]
            if np.linalg.norm(placed - T_target[:3, 3]) > FREE_POSE_TOL:
                problems.append("set_free_pose does not place a free-floating hand's palm")
    except Exception as exc:
        problems.append(f"free-floating world failed: {type(exc).__name__}: {exc}")
    return problems
