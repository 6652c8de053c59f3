"""What a robot is: pure data, no simulator import.

A `HandDescription` or `ArmDescription` names a URDF model and says, in SI units, which
joints it drives and within which limits, where its named frames are, which links make
up each real finger, and (for hands) the preshapes and the human-grasp -> preshape
mapping table. Backends, the planner and the metric read these; none of them hard-codes
a particular robot.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from graspframe.common.errors import DescriptionError, UnknownNameError
from graspframe.common.grasps import HumanGrasp
from graspframe.hal.mountings import AdapterShape, Mounting
from graspframe.model_files.urdf_model import FrameOffset, ModelFile, UrdfModel, load_model_file

FINGERTIP_FRAMES_KEY = "fingertip_frames"
"""The key of `HandDescription.extras` that named each real finger's fingertip frame
before `HandDescription.fingertip_frames` did (still read, with a DeprecationWarning)."""

__all__ = [
    "FINGERTIP_FRAMES_KEY",
    "AdapterShape",
    "ArmDescription",
    "Coupling",
    "DesignObject",
    "DriveGains",
    "FrameOffset",
    "HandDescription",
    "HandPreshape",
    "JointSpec",
    "Mounting",
    "joints_by_name",
]


def joints_by_name(
    arm_joint_names: Sequence[str], q_arm: ArrayLike | None, q_hand: Mapping[str, float]
) -> dict[str, float]:
    """Every joint's value by name [rad], for a model of the hand on its arm: the arm's,
    an array in `arm_joint_names` order (None: a hand without an arm), and the hand's,
    by name (with the model's mimic followers where the caller added them)."""
    q = {name: float(value) for name, value in q_hand.items()}
    if q_arm is not None:
        values = np.asarray(q_arm, dtype=float).ravel()
        q.update(zip(arm_joint_names, values.tolist(), strict=True))
    return q


def _warn_urdf(kind: str) -> None:
    warnings.warn(
        f"{kind}.urdf() is deprecated: a description is data; load its model with "
        "graspframe.robot_models.model.model_of(description)",
        DeprecationWarning,
        stacklevel=3,
    )


@dataclass(frozen=True)
class JointSpec:
    """One joint of a model and its limits.

    lower, upper: position limits [rad] (or [m] for prismatic joints)
    max_velocity [rad/s], max_acceleration [rad/s^2], max_jerk [rad/s^3]: motion limits;
        acceleration and jerk matter for arm joints (trajectory generation) and may be
        left at infinity for hand joints.
    max_effort: [N m] (or [N]) the drive's force limit.
    """

    name: str
    lower: float
    upper: float
    max_velocity: float
    max_effort: float
    max_acceleration: float = math.inf
    max_jerk: float = math.inf

    def contains(self, q: float, tol: float = 1e-9) -> bool:
        return self.lower - tol <= q <= self.upper + tol

    def excess(self, q: float) -> float:
        """[rad] ([m]) past the nearer position limit; 0 within them."""
        return max(self.lower - q, q - self.upper, 0.0)


@dataclass(frozen=True)
class Coupling:
    """`follower` = multiplier * `leader` + offset [rad].

    in_model: True when the URDF itself declares the coupling as a <mimic> joint (the
    simulator enforces it); False when the hand's controller enforces it, as for the
    Barrett distal joints whose coupling breaks away under contact torque.
    breakaway_torque: [N m] for controller couplings: when closing and the leader's drive
    torque exceeds it, the leader stops where it is (held, as by the Barrett's worm gear)
    and only the follower keeps closing. None: the coupling never breaks.
    """

    follower: str
    leader: str
    multiplier: float
    offset: float = 0.0
    in_model: bool = True
    breakaway_torque: float | None = None


@dataclass(frozen=True)
class DriveGains:
    """Joint-space PD drive of a simulated actuator: stiffness [N m/rad], damping
    [N m s/rad], force limit [N m] ([N], [N/m], [N s/m] for a prismatic joint).
    Compliant (fluidic) hands use a low stiffness.

    armature: [kg m^2] ([kg] for a prismatic joint) inertia the actuator adds to its
    joint, as a motor's rotor does through its gear. A simulator solves joint limits,
    drives and contacts together by iteration; light links (a finger phalanx of a few
    grams, the virtual links of the floating base) leave that badly conditioned, so a
    contact pushing hard moves a joint past its limit and a stiff drive off its target.
    The armature conditions it (docs/robots.md, "Joint limits and drives in the
    simulator").
    """

    stiffness: float
    damping: float
    force_limit: float
    armature: float = 0.0


@dataclass(frozen=True)
class DesignObject:
    """The object a preshape (or a human posture) is shaped for, where it sits in the
    palm frame when held.

    shape: "cylinder" or "sphere" (a box is described by its enclosing cylinder);
    centre: [m] palm frame; axis: unit vector, palm frame (cylinders); radius, length: [m]
    (length for cylinders).
    """

    shape: str
    centre: tuple[float, float, float]
    radius: float
    axis: tuple[float, float, float] | None = None
    length: float | None = None

    def extent_along(self, n_palm: ArrayLike) -> float:
        """[m] half-extent of the object along the unit palm-frame direction n_palm."""
        n = np.asarray(n_palm, dtype=float)
        n = n / np.linalg.norm(n)
        if self.shape == "cylinder" and self.axis is not None and self.length is not None:
            u = np.asarray(self.axis, dtype=float)
            u = u / np.linalg.norm(u)
            along = abs(float(n @ u))
            return along * self.length / 2 + math.sqrt(max(0.0, 1.0 - along**2)) * self.radius
        return self.radius


@dataclass(frozen=True)
class HandPreshape:
    """A preshape: joint targets [rad] for the open and the closed hand, and where the
    object sits in the hand.

    open_q: the configuration the hand takes before approaching.
    closed_q: the targets commanded when closing; on an object the fingers stop
        earlier, in free space they reach it.
    delta: palm-to-fingertip distance [m] of the open preshape along the palm normal,
        the standoff of the non-volar strategy (docs/method.md#the-grasp-strategy).
    grasp_center: [m] palm-frame point where the object's centroid should sit when the
        hand closes on it. None: the design object's centre, else (0, 0, delta). For a
        volar grasp only its x and y count: the object rests on the palm (see
        `volar_centre_height` for thin objects).
    design_object: the object the preshape is shaped for, in the palm frame where the
        hand holds it; the planner scales the grasp centre's height to the real object
        and the model checks (`graspframe.testing`) hold it with the hand alone.
    roll: [rad] preferred turn of the robot palm about its normal relative to the human
        palm (0: the palm frames coincide).
    opposed: pairs of real fingers that close towards each other (a thumb and a finger);
        the model checks test that closing in free space brings each pair together.
    volar_centre_height: [m] used as a volar preshape: the height above the palm where
        the closing fingers hold a thin object's centroid. The volar approach finds the
        object with the palm; the hand then backs off until the centroid is at this
        height. An object whose half-extent is larger rests on the palm. None: every
        object rests on the palm.
    stop_direction: palm-frame unit vector along the palm surface pointing at fingers
        that stay where they are and take the object's rim (a non-volar grasp whose
        other fingers, e.g. a sweeping thumb, come to the object wherever it is). An
        object larger or smaller than the design object then keeps its extent along
        it where the design object's is: its centre moves back by the difference of
        the extents. None: the grasp centre's x and y hold for every size.
    """

    name: str
    open_q: Mapping[str, float]
    closed_q: Mapping[str, float]
    delta: float
    grasp_center: tuple[float, float, float] | None = None
    design_object: DesignObject | None = None
    roll: float = 0.0
    opposed: tuple[tuple[str, str], ...] = ()
    volar_centre_height: float | None = None
    stop_direction: tuple[float, float, float] | None = None

    @property
    def grasp_center_palm(self) -> tuple[float, float, float]:
        """[m] where the object's centroid sits when held, in the palm frame."""
        if self.grasp_center is not None:
            return self.grasp_center
        if self.design_object is not None:
            return self.design_object.centre
        return (0.0, 0.0, self.delta)


@dataclass(frozen=True)
class HandDescription:
    """A robot (or human) hand.

    model_path: URDF file of the hand alone, as shipped (meshes, visuals, package://
        names: graspframe/model_files/urdf_model.py).
    root_link: the mount link: the link (or added frame, one of `frames`) bolted to the
        arm's flange, its origin on the mounting interface, +z away from the arm (or the
        link that floats freely). The model is rooted there whatever link the file is
        rooted at (graspframe/model_files/urdf_tree.py).
    joints: every actuated joint, followers of in-model couplings excluded.
    couplings: joint couplings (see `Coupling`).
    palm_frame: a link whose frame is the palm frame: origin at the centre of the palm
        surface, +z out of the palm towards the object, +x towards the fingertips (for
        fingers that stand out of the palm along +z, as a gripper's jaws: along the
        direction they close on, the jaw stroke).
    palm_sensor_link: the link whose contacts count as "palm touches" for the volar
        strategy.
    real_fingers: real finger name -> links; must include PALM.
    preshapes: preshape name -> preshape.
    grasp_map: every HumanGrasp -> a preshape name (for the human hand: its posture).
    drive: PD gains for the simulated finger drives.
    synchronised_closing: True when the hand's controller moves to a commanded posture
        in a straight line in joint space, every joint arriving together (the closing
        the planner's kinematic closing models); False when each joint moves at its own
        velocity limit, as independent finger motors do (graspframe/hal/hand_control.py).
    mass: [kg] total, informative.
    extras: further facts about the hand, by key, for plugins (graspframe reads none).
    fingertip_frames: real finger name -> the link or added frame at that finger's tip,
        for each finger (not the palm); the contract checks that they are links of the
        model. Empty when the hand does not name them.
    mountings: name -> `Mounting`: adapters the planner may put between the arm flange
        and the hand, in this order, when the arm finds no path with the hand's root link
        bolted straight onto the flange (graspframe/strategy/arm_path.py).
    packages: package name -> folder, for package:// mesh names in the model file.
    frames: frames the model file lacks (palm frame, palm pad, fingertips), by name,
        each fixed to an existing link at an offset; the names may be used wherever a
        link name is (palm_frame, palm_sensor_link, real_fingers).
    """

    name: str
    model_path: Path
    root_link: str
    joints: tuple[JointSpec, ...]
    palm_frame: str
    palm_sensor_link: str
    real_fingers: Mapping[str, tuple[str, ...]]
    preshapes: Mapping[str, HandPreshape]
    grasp_map: Mapping[HumanGrasp, str]
    drive: DriveGains
    couplings: tuple[Coupling, ...] = ()
    synchronised_closing: bool = False
    mass: float = 0.0
    summary: str = ""
    extras: Mapping[str, object] = field(default_factory=dict)
    fingertip_frames: Mapping[str, str] = field(default_factory=dict)
    mountings: Mapping[str, Mounting] = field(default_factory=dict)
    packages: Mapping[str, Path] = field(default_factory=dict)
    frames: Mapping[str, FrameOffset] = field(default_factory=dict)

    def __post_init__(self) -> None:
        frames = self.fingertip_frames
        if not frames and FINGERTIP_FRAMES_KEY in self.extras:
            warnings.warn(
                f"hand {self.name!r}: extras[{FINGERTIP_FRAMES_KEY!r}] is deprecated: give "
                "HandDescription(fingertip_frames=...)",
                DeprecationWarning,
                stacklevel=3,
            )
            frames = self.extras[FINGERTIP_FRAMES_KEY]  # type: ignore[assignment]
        if not isinstance(frames, Mapping) or not all(
            isinstance(finger, str) and isinstance(frame, str) for finger, frame in frames.items()
        ):
            raise DescriptionError(
                f"hand {self.name!r}: fingertip_frames must map real finger names to frame "
                f"names, got {frames!r}"
            )
        object.__setattr__(self, "fingertip_frames", dict(frames))

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    def model_file(self) -> ModelFile:
        """How the hand's model file is read (data: graspframe.robot_models.model.model_of
        reads it): rooted at its mount link."""
        return ModelFile(
            self.model_path,
            self.packages,
            self.frames,
            root_at=self.root_link,
            root_role="the mount link",
        )

    def urdf(self) -> UrdfModel:
        """The hand's model. Deprecated: use graspframe.robot_models.model.model_of(hand)."""
        _warn_urdf("HandDescription")
        return load_model_file(self.model_file())

    def mounting(self, name: str) -> Mounting:
        try:
            return self.mountings[name]
        except KeyError:
            raise UnknownNameError(
                f"mounting of hand {self.name!r}", name, self.mountings
            ) from None

    def joint(self, name: str) -> JointSpec:
        for j in self.joints:
            if j.name == name:
                return j
        raise UnknownNameError(f"joint of hand {self.name!r}", name, self.joint_names)

    def preshape(self, name: str) -> HandPreshape:
        try:
            return self.preshapes[name]
        except KeyError:
            raise UnknownNameError(
                f"preshape of hand {self.name!r}", name, self.preshapes
            ) from None

    def preshape_for(self, grasp: HumanGrasp) -> HandPreshape:
        """The preshape this hand uses for a human grasp (its mapping table)."""
        if grasp not in self.grasp_map:
            raise DescriptionError(
                f"hand {self.name!r} has no mapping for grasp {grasp.value!r}; "
                f"it maps: {', '.join(g.value for g in self.grasp_map)}"
            )
        return self.preshape(self.grasp_map[grasp])

    def with_model_followers(self, q_by_joint: Mapping[str, float]) -> dict[str, float]:
        """`q_by_joint` plus the followers of in-model (<mimic>) couplings [rad], for tools
        that read the URDF without mimic support (each follower is a joint there)."""
        full = dict(q_by_joint)
        for c in self.couplings:
            if c.in_model and c.leader in full:
                full[c.follower] = c.multiplier * full[c.leader] + c.offset
        return full

    def finger_of_link(self) -> dict[str, str]:
        """link name -> real finger name."""
        return {link: finger for finger, links in self.real_fingers.items() for link in links}

    @property
    def finger_names(self) -> tuple[str, ...]:
        return tuple(self.real_fingers)


@dataclass(frozen=True)
class ArmDescription:
    """A robot arm.

    model_path: URDF file of the arm, as shipped (graspframe/model_files/urdf_model.py).
    base_link: the link (or added frame) fixed to the world; the model is rooted there
        whatever link the file is rooted at.
    flange_link: the tool flange link (+z out of the flange); a hand's root link is
        fixed to it. Every link the file has beyond it (a vendor's own gripper) is
        dropped; when it is one of `frames`, everything beyond that frame's parent.
    joints: the arm joints in chain order, with position, velocity, acceleration and
        jerk limits (ruckig needs all four).
    home_q: [rad] a comfortable configuration to start from, one value per joint.
    drive: PD gains for the simulated joint drives.
    packages: package name -> folder, for package:// mesh names in the model file.
    frames: frames the model file lacks (e.g. the flange), each fixed to an existing
        link at an offset.
    name_prefix: put before every link and joint name of the model file (set by
        `with_name_prefix` when a hand mounted on the arm has names of its own arm's);
        every name in this description already includes it.
    tool_links: links (names as in the model file, without the prefix) whose shapes are
        the vendor's own tool merged into the arm (the Kinova JACO2's last link carries
        its gripper's housing): left out, since the mounted hand replaces that tool.
    """

    name: str
    model_path: Path
    base_link: str
    flange_link: str
    joints: tuple[JointSpec, ...]
    home_q: tuple[float, ...]
    drive: DriveGains
    summary: str = ""
    packages: Mapping[str, Path] = field(default_factory=dict)
    frames: Mapping[str, FrameOffset] = field(default_factory=dict)
    name_prefix: str = ""
    tool_links: tuple[str, ...] = ()

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    def model_file(self) -> ModelFile:
        """How the arm's model file is read (data: graspframe.robot_models.model.model_of
        reads it): rooted at its base, cut at the flange, without its vendor tool's
        shapes."""
        offset = self.frames.get(self.flange_link)
        cut_below = self.flange_link if offset is None else offset.parent
        return ModelFile(
            self.model_path,
            self.packages,
            self.frames,
            cut_below,
            self.name_prefix,
            root_at=self.base_link,
            root_role="the base link",
            tool_links=self.tool_links,
        )

    def urdf(self) -> UrdfModel:
        """The arm's model. Deprecated: use graspframe.robot_models.model.model_of(arm)."""
        _warn_urdf("ArmDescription")
        return load_model_file(self.model_file())

    def with_name_prefix(self, prefix: str) -> ArmDescription:
        """The same arm with `prefix` before every link and joint name."""
        from dataclasses import replace

        def renamed(offset: FrameOffset) -> FrameOffset:
            return replace(offset, parent=prefix + offset.parent)

        return replace(
            self,
            base_link=prefix + self.base_link,
            flange_link=prefix + self.flange_link,
            joints=tuple(replace(j, name=prefix + j.name) for j in self.joints),
            frames={prefix + name: renamed(f) for name, f in self.frames.items()},
            name_prefix=self.name_prefix + prefix,
        )

    @property
    def dof(self) -> int:
        return len(self.joints)
