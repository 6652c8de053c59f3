"""Reading URDF models with Pinocchio: joints, limits and links, for checks and kinematics."""

from __future__ import annotations

import functools
from collections.abc import Set as AbstractSet
from dataclasses import dataclass
from pathlib import Path

from graspframe.errors import DescriptionError


@dataclass(frozen=True)
class UrdfJoint:
    """A movable joint as Pinocchio reads it: limits [rad] and velocity limit [rad/s]."""

    name: str
    lower: float
    upper: float
    max_velocity: float
    max_effort: float


@dataclass(frozen=True)
class UrdfSummary:
    """What a URDF declares: movable joints (mimic followers included) and link names."""

    joints: dict[str, UrdfJoint]
    links: frozenset[str]


def load_pinocchio_model(path: Path | str, mimic: bool = False):
    """The Pinocchio model of a URDF file; a clear error if it is missing or malformed.

    mimic=True makes <mimic> followers part of their leader joint (reduced configuration).
    """
    import pinocchio as pin

    path = Path(path)
    if not path.is_file():
        raise DescriptionError(f"model file not found: {path}")
    try:
        return pin.buildModelFromUrdf(str(path), mimic)
    except Exception as exc:
        raise DescriptionError(f"Pinocchio cannot load {path.name}: {exc}") from exc


@functools.lru_cache(maxsize=64)
def summarize_urdf(path: Path | str) -> UrdfSummary:
    """Joint limits and link names of a URDF, read by Pinocchio (each follower separately)."""
    import pinocchio as pin

    model = load_pinocchio_model(path, mimic=False)
    joints: dict[str, UrdfJoint] = {}
    for joint_id in range(1, model.njoints):
        joint = model.joints[joint_id]
        if joint.nq != 1:  # only revolute/prismatic joints are actuated in our models
            continue
        iq, iv = joint.idx_q, joint.idx_v
        name = model.names[joint_id]
        joints[name] = UrdfJoint(
            name=name,
            lower=float(model.lowerPositionLimit[iq]),
            upper=float(model.upperPositionLimit[iq]),
            max_velocity=float(model.velocityLimit[iv]),
            max_effort=float(model.effortLimit[iv]),
        )
    links = frozenset(f.name for f in model.frames if f.type == pin.FrameType.BODY)
    return UrdfSummary(joints=joints, links=links)


class CollisionModel:
    """A URDF's collision shapes placed by Pinocchio forward kinematics.

    Used to check geometry facts: which shapes contain a point (palm frame direction),
    which links collide in a configuration (self-collision of preshapes), and to draw a
    model. Joints are set by name; joints not given stay at zero. Followers of <mimic>
    couplings are ordinary joints here (mimic=False), so callers give their values.
    """

    def __init__(self, urdf_path: Path | str):
        import pinocchio as pin

        self._pin = pin
        self.model = load_pinocchio_model(urdf_path, mimic=False)
        self.geometry = pin.buildGeomFromUrdf(
            self.model, str(urdf_path), pin.GeometryType.COLLISION
        )
        self.data = self.model.createData()
        self.geometry_data = pin.GeometryData(self.geometry)
        self.q = pin.neutral(self.model)
        self.link_of_shape = [
            self.model.frames[g.parentFrame].name for g in self.geometry.geometryObjects
        ]
        self.place({})

    def place(self, q_by_joint: dict[str, float]) -> None:
        """Set joint positions [rad] by name and update every placement."""
        pin = self._pin
        self.q = pin.neutral(self.model)
        for name, value in q_by_joint.items():
            if not self.model.existJointName(name):
                raise DescriptionError(f"joint {name!r} is not in the model")
            self.q[self.model.joints[self.model.getJointId(name)].idx_q] = value
        pin.forwardKinematics(self.model, self.data, self.q)
        pin.updateFramePlacements(self.model, self.data)
        pin.updateGeometryPlacements(self.model, self.data, self.geometry, self.geometry_data)

    def T_root_frame(self, frame: str):
        """4x4 pose of a link or frame in the model's root frame."""
        if not self.model.existFrame(frame):
            raise DescriptionError(f"frame {frame!r} is not in the model")
        return self.data.oMf[self.model.getFrameId(frame)].homogeneous.copy()

    def shapes(self):
        """(link name, coal geometry, 4x4 pose in the root frame) of every collision shape."""
        for index, obj in enumerate(self.geometry.geometryObjects):
            pose = self.geometry_data.oMg[index].homogeneous.copy()
            yield self.link_of_shape[index], obj.geometry, pose

    def links_containing(self, p_root) -> list[str]:
        """Links with a box, cylinder or sphere shape that contains the point p_root [m]."""
        import numpy as np

        inside = []
        for link, shape, T_root_shape in self.shapes():
            R, t = T_root_shape[:3, :3], T_root_shape[:3, 3]
            p = R.T @ (np.asarray(p_root, dtype=float) - t)
            kind = type(shape).__name__
            if kind == "Box":
                hit = bool(np.all(np.abs(p) <= shape.halfSide))
            elif kind == "Cylinder":
                hit = bool(np.hypot(p[0], p[1]) <= shape.radius and abs(p[2]) <= shape.halfLength)
            elif kind == "Sphere":
                hit = bool(np.linalg.norm(p) <= shape.radius)
            else:
                raise DescriptionError(f"link {link!r}: cannot test points against a {kind}")
            if hit and link not in inside:
                inside.append(link)
        return inside

    def parent_link(self, link: str) -> str | None:
        """The link a link hangs from (through its joint), None for the root."""
        frame = self.model.frames[self.model.getFrameId(link)]
        parent_frame = self.model.frames[frame.parentFrame]
        while parent_frame.type != self._pin.FrameType.BODY and parent_frame.name != "universe":
            parent_frame = self.model.frames[parent_frame.parentFrame]
        return None if parent_frame.name == "universe" else parent_frame.name

    def colliding_links(
        self, ignore: AbstractSet[frozenset[str]] = frozenset()
    ) -> list[tuple[str, str]]:
        """Pairs of distinct links whose shapes intersect, except adjacent links (a joint
        joins them, their shapes meet by design) and the pairs in `ignore`."""
        import coal

        placed = list(self.shapes())
        hits: set[tuple[str, str]] = set()
        for i in range(len(placed)):
            for j in range(i + 1, len(placed)):
                link_a, shape_a, T_a = placed[i]
                link_b, shape_b, T_b = placed[j]
                pair = frozenset((link_a, link_b))
                if link_a == link_b or pair in ignore:
                    continue
                if self.parent_link(link_a) == link_b or self.parent_link(link_b) == link_a:
                    continue
                request, result = coal.CollisionRequest(), coal.CollisionResult()
                tf_a = coal.Transform3s(T_a[:3, :3], T_a[:3, 3])
                tf_b = coal.Transform3s(T_b[:3, :3], T_b[:3, 3])
                if coal.collide(shape_a, tf_a, shape_b, tf_b, request, result):
                    hits.add(tuple(sorted((link_a, link_b))))
        return sorted(hits)
