"""The kinematic facts a hand draft reads from a URDF (graspframe/specs/draft.py):
its joints, the fingers found in it, forward kinematics in the palm link's frame, and
where a fingertip moves as its joints close."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from graspframe.model_files.coupled_limits import leader_ranges
from graspframe.model_files.urdf_model import UrdfModel

MOVING = ("revolute", "prismatic", "continuous")
PLACING_JOINTS = 2  # a finger's placing joints tried: those of the largest range


@dataclass(frozen=True)
class Joint:
    """A URDF joint as the draft reads it: limits [rad or m], axis in its own frame."""

    name: str
    kind: str
    parent: str
    child: str
    lower: float
    upper: float
    effort: float
    velocity: float
    mimic: str | None

    @property
    def moving(self) -> bool:
        return self.kind in MOVING

    @property
    def rest(self) -> float:
        """The value nearest 0 within the limits (the extended finger, in every URDF
        seen: the vendors model the flat hand at 0)."""
        return min(max(0.0, self.lower), self.upper)


Joints = Mapping[str, "Joint"]
Axes = Mapping[str, NDArray[np.float64]]


@dataclass
class DraftFinger:
    """A finger found in the model: its links (root to tip), its moving joints (root to
    tip, <mimic> followers included), the joints that curl it and those that place it,
    each joint's closing sign, its tip frame and whether that frame is added."""

    name: str
    links: list[str]
    joints: list[str]
    flexion: list[str]
    placing: list[str]
    closing_sign: dict[str, float]
    tip_frame: str
    tip_offset: tuple[str, NDArray[np.float64]] | None = None  # (parent link, xyz [m])


def read_joints(model: UrdfModel) -> dict[str, Joint]:
    joints = {}
    for element in model.root().findall("joint"):
        parent, child = element.find("parent"), element.find("child")
        if parent is None or child is None:
            continue
        kind = element.get("type", "fixed")
        limit = element.find("limit")
        values = {} if limit is None else limit.attrib
        mimic = element.find("mimic")
        lower = float(values.get("lower", -math.pi if kind == "continuous" else 0.0))
        upper = float(values.get("upper", math.pi if kind == "continuous" else 0.0))
        name = element.get("name", "")
        joints[name] = Joint(
            name, kind, parent.get("link", ""), child.get("link", ""), lower, upper,
            float(values.get("effort", 0.0)), float(values.get("velocity", 0.0)),
            None if mimic is None else mimic.get("joint"),
        )  # fmt: skip
    # a leader goes only as far as its followers' limits let it (model_files/coupled_limits)
    ranges = leader_ranges(
        {n: (j.lower, j.upper) for n, j in joints.items()}, model.mimic_followers
    )
    return {n: replace(j, lower=ranges[n][0], upper=ranges[n][1]) for n, j in joints.items()}


class Kinematics:
    """Forward kinematics of the model (Pinocchio), every joint set by name, positions
    in the palm link's frame."""

    def __init__(self, model: UrdfModel, palm_link: str):
        from graspframe.robot_models.model import CollisionModel

        self.collision = CollisionModel(model)
        self.palm_link = palm_link

    def place(self, q: Mapping[str, float]) -> None:
        self.q = dict(q)
        self.collision.place(self.q)

    def collision_q(self) -> dict[str, float]:
        """The joint values last placed."""
        return dict(self.q)

    def T(self, frame: str) -> NDArray[np.float64]:
        """The frame's pose in the palm link's frame."""
        T_root_palm = self.collision.T_root_frame(self.palm_link)
        return np.linalg.inv(T_root_palm) @ self.collision.T_root_frame(frame)

    def joint_axis_origin(
        self, joint: Joint, axis_local: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(unit axis, origin) of a joint in the palm link's frame: its child link's
        frame carries the joint's axis."""
        T = self.T(joint.child)
        return T[:3, :3] @ axis_local, T[:3, 3]

    def link_points(self, links: Sequence[str]) -> NDArray[np.float64]:
        """(N, 3) the collision shapes' points of `links`, in the palm link's frame."""
        T_palm_root = np.linalg.inv(self.collision.T_root_frame(self.palm_link))
        wanted = set(links)
        points = []
        for index, (link, _shape, T_root_shape) in enumerate(self.collision.shapes()):
            if link in wanted:
                T = T_palm_root @ T_root_shape
                points.append(self.collision.local_points(index) @ T[:3, :3].T + T[:3, 3])
        return np.vstack(points) if points else np.zeros((0, 3))


def joint_axes(model: UrdfModel) -> dict[str, NDArray[np.float64]]:
    axes = {}
    for element in model.root().findall("joint"):
        axis = element.find("axis")
        xyz = (
            [1.0, 0.0, 0.0]
            if axis is None
            else [float(v) for v in axis.get("xyz", "1 0 0").split()]
        )
        vector = np.asarray(xyz, dtype=float)
        axes[element.get("name", "")] = vector / max(np.linalg.norm(vector), 1e-12)
    return axes


def tip_position(finger: DraftFinger, kin: Kinematics) -> NDArray[np.float64]:
    if finger.tip_offset is None:
        return kin.T(finger.tip_frame)[:3, 3]
    link, xyz = finger.tip_offset
    return (kin.T(link) @ np.append(xyz, 1.0))[:3]


def tip_motion(
    finger: DraftFinger, joints: Joints, kin: Kinematics, axes: Axes, name: str
) -> NDArray[np.float64]:
    """d(tip)/dq of joint `name` [m/rad or m/m] in the palm link's frame, now."""
    joint = joints[name]
    axis, origin = kin.joint_axis_origin(joint, axes[name])
    if joint.kind == "prismatic":
        return axis
    return np.asarray(np.cross(axis, tip_position(finger, kin) - origin), dtype=float)


def closing_direction(
    finger: DraftFinger, joints: Joints, kin: Kinematics, axes: Axes
) -> NDArray[np.float64]:
    """The unit direction the fingertip moves as its flexion joints close, now."""
    motion = sum(
        finger.closing_sign[name] * tip_motion(finger, joints, kin, axes, name)
        for name in finger.flexion
        if joints[name].mimic is None
    )
    vector = np.asarray(motion, dtype=float)
    return vector / max(float(np.linalg.norm(vector)), 1e-12)


def placing_grid(finger: DraftFinger, joints: Joints, count: int = 3) -> list[dict[str, float]]:
    """Values of the finger's placing joints to try: `count` across the range (lower,
    middle, upper for 3) of each of the two with the largest range (not followers)."""
    grid: list[dict[str, float]] = [{}]
    # the two placing joints of the largest range (a thumb's rotation and abduction)
    placing = [n for n in finger.placing if joints[n].mimic is None]
    placing = sorted(placing, key=lambda n: joints[n].lower - joints[n].upper)[:PLACING_JOINTS]
    for name in placing:
        joint = joints[name]
        values = np.linspace(joint.lower, joint.upper, count)
        grid = [{**g, name: float(v)} for g in grid for v in values]
    return grid
