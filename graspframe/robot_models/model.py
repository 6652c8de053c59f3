"""Reading robot models with Pinocchio: joints, limits, links and collision shapes.

Every function takes a `UrdfModel` (graspframe/model_files/urdf_model.py: the URDF text in memory,
collision meshes already replaced by convex pieces). Pinocchio loads each piece as a
triangle mesh; `collision_geometry` turns those into coal `Convex` shapes, so distances
and collisions are those of the solid piece (as the simulator sees it), not of its
surface.
"""

from __future__ import annotations

import functools
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, replace

from graspframe.common.errors import DescriptionError
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.model_files.coupled_limits import leader_ranges
from graspframe.model_files.urdf_model import UrdfModel, load_model_file


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


def load_pinocchio_model(model: UrdfModel, mimic: bool = False):
    """The Pinocchio model of a robot model; a clear error if Pinocchio cannot read it.

    mimic=True makes <mimic> followers part of their leader joint (reduced configuration).
    """
    import pinocchio as pin

    try:
        return pin.buildModelFromXML(model.text, mimic)
    except Exception as exc:
        raise DescriptionError(f"Pinocchio cannot load {model.describe()}: {exc}") from exc


def collision_geometry_model(model: UrdfModel, pinocchio_model):
    """Pinocchio's collision geometry model of `model`, every mesh as a coal `Convex`
    (the meshes are convex pieces: graspframe/model_files/convex.py)."""
    import coal
    import pinocchio as pin

    try:
        geometry = pin.buildGeomFromUrdfString(
            pinocchio_model, model.text, pin.GeometryType.COLLISION
        )
    except Exception as exc:
        raise DescriptionError(
            f"Pinocchio cannot load the collision shapes of {model.describe()}: {exc}"
        ) from exc
    for geometry_object in geometry.geometryObjects:
        if isinstance(geometry_object.geometry, coal.BVHModelBase):
            mesh = geometry_object.geometry
            mesh.buildConvexRepresentation(False)
            geometry_object.geometry = mesh.convex
    return geometry


def summarize_urdf(model: UrdfModel) -> UrdfSummary:
    """Joint limits and link names of a model, read by Pinocchio (each follower
    separately; a leader's limits cut to what its followers' let it reach,
    graspframe/model_files/coupled_limits.py)."""
    return _summary(model.text, model.describe())


def model_of(description: HandDescription | ArmDescription) -> UrdfModel:
    """A hand's or an arm's model as every tool loads it: its `model_file()`, read once
    per process (graspframe.model_files.urdf_model.load_model_file)."""
    return load_model_file(description.model_file())


@functools.lru_cache(maxsize=64)
def _summary(text: str, name: str) -> UrdfSummary:
    import pinocchio as pin

    model = load_pinocchio_model(UrdfModel(name, text), mimic=False)
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
    # a <mimic> leader goes only as far as its followers' limits let it
    ranges = leader_ranges(
        {n: (j.lower, j.upper) for n, j in joints.items()}, UrdfModel(name, text).mimic_followers
    )
    joints = {n: replace(j, lower=ranges[n][0], upper=ranges[n][1]) for n, j in joints.items()}
    links = frozenset(f.name for f in model.frames if f.type == pin.FrameType.BODY)
    return UrdfSummary(joints=joints, links=links)


def _inside_convex(points, p, tolerance: float = 1e-9) -> bool:
    """Whether the point p lies in the convex hull of `points` (both in one frame) [m]."""
    import numpy as np
    from scipy.spatial import ConvexHull

    equations = ConvexHull(points).equations
    return bool(np.all(equations[:, :3] @ p + equations[:, 3] <= tolerance))


class CollisionModel:
    """A model's collision shapes placed by Pinocchio forward kinematics.

    Used to check geometry facts: which shapes contain a point (palm frame direction),
    which links collide in a configuration (self-collision of preshapes), and to draw a
    model. Joints are set by name; joints not given stay at zero. Followers of <mimic>
    couplings are ordinary joints here (mimic=False), so callers give their values.
    """

    def __init__(self, urdf: UrdfModel):
        import pinocchio as pin

        self._pin = pin
        self.urdf = urdf
        self.model = load_pinocchio_model(urdf, mimic=False)
        self.geometry = collision_geometry_model(urdf, self.model)
        self.data = self.model.createData()
        self.geometry_data = pin.GeometryData(self.geometry)
        self.q = pin.neutral(self.model)
        self.link_of_shape = [
            self.model.frames[g.parentFrame].name for g in self.geometry.geometryObjects
        ]
        self._local_points: dict[int, object] = {}  # shape index -> (n, 3) in its frame
        self._parent_links: dict[str, str | None] = {}
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
        """Links with a shape (box, cylinder, sphere or convex piece) that contains the
        point p_root [m]."""
        import numpy as np

        from graspframe.robot_models.shapes import convex_points

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
            elif kind == "Convex":
                hit = _inside_convex(convex_points(shape), p)
            else:
                raise DescriptionError(f"link {link!r}: cannot test points against a {kind}")
            if hit and link not in inside:
                inside.append(link)
        return inside

    def local_points(self, index: int):
        """(n, 3) [m] points bounding shape `index` (the order of shapes()) in its own
        frame: robot_models/shapes.py's local_shape_points, computed once."""
        if index not in self._local_points:
            from graspframe.robot_models.shapes import local_shape_points

            geometry = self.geometry.geometryObjects[index].geometry
            self._local_points[index] = local_shape_points(geometry)
        return self._local_points[index]

    def bounding_sphere(self, index: int):
        """(centre (3,) in the shape's frame, radius [m]) of a sphere holding shape
        `index`, 1 mm wider (touching counts as colliding); an infinite radius for kinds
        local_points cannot bound."""
        import numpy as np

        kind = type(self.geometry.geometryObjects[index].geometry).__name__
        if kind not in ("Box", "Cylinder", "Sphere", "Convex", "Capsule"):
            return np.zeros(3), np.inf
        points = self.local_points(index)
        centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
        return centre, float(np.linalg.norm(points - centre, axis=1).max()) + 0.001

    def parent_link(self, link: str) -> str | None:
        """The link a link hangs from (through its joint), None for the root."""
        if link not in self._parent_links:
            self._parent_links[link] = self._find_parent_link(link)
        return self._parent_links[link]

    def _find_parent_link(self, link: str) -> str | None:
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
        import numpy as np

        placed = list(self.shapes())
        spheres = [self.bounding_sphere(index) for index in range(len(placed))]
        centres = np.array(
            [T[:3, :3] @ c + T[:3, 3] for (_l, _s, T), (c, _r) in zip(placed, spheres, strict=True)]
        ).reshape(-1, 3)
        radii = np.array([r for _c, r in spheres])
        hits: set[tuple[str, str]] = set()
        for i in range(len(placed)):
            # bounding spheres apart: the shapes are (the cheap test first)
            apart = np.linalg.norm(centres - centres[i], axis=1) > radii + radii[i]
            for j in range(i + 1, len(placed)):
                link_a, shape_a, T_a = placed[i]
                link_b, shape_b, T_b = placed[j]
                pair = frozenset((link_a, link_b))
                if apart[j] or link_a == link_b or pair in ignore:
                    continue
                if self.parent_link(link_a) == link_b or self.parent_link(link_b) == link_a:
                    continue
                request, result = coal.CollisionRequest(), coal.CollisionResult()
                tf_a = coal.Transform3s(T_a[:3, :3], T_a[:3, 3])
                tf_b = coal.Transform3s(T_b[:3, :3], T_b[:3, 3])
                if coal.collide(shape_a, tf_a, shape_b, tf_b, request, result):
                    hits.add(tuple(sorted((link_a, link_b))))
        return sorted(hits)
