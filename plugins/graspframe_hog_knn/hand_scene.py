"""Triangle meshes of the human hand model holding its object, in the palm frame.

The hand is drawn from the collision shapes of robots/human/human.urdf (boxes, cylinders
and spheres placed by Pinocchio forward kinematics), the object from its
ObjectDescription placed by `reference_placement`. Everything is expressed in the human
palm frame (`hh_palm_frame`: +x to the fingertips, +z out of the palm) [m].
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import inv_T, transform_points
from graspframe.hal.objects import ObjectDescription
from graspframe.robot_models import shapes
from graspframe.robot_models.model import model_of
from graspframe.robot_models.shapes import geometry_primitive, unit_primitive, unit_scale

PALM_FRAME = "hh_palm_frame"


@dataclass(frozen=True)
class Mesh:
    """Unindexed triangles: positions (3N, 3) [m] and unit normals (3N, 3)."""

    positions: NDArray[np.float32]
    normals: NDArray[np.float32]

    def transformed(self, T: NDArray[np.float64], scale: float = 1.0) -> Mesh:
        """This mesh scaled by `scale` about its origin, then moved by the 4x4 pose T."""
        return Mesh(
            transform_points(T, self.positions * scale).astype(np.float32),
            (self.normals @ T[:3, :3].T).astype(np.float32),
        )


def _unindexed(mesh: trimesh.Trimesh, smooth: bool) -> Mesh:
    faces = mesh.faces.reshape(-1)
    positions = mesh.vertices[faces]
    normals = mesh.vertex_normals[faces] if smooth else np.repeat(mesh.face_normals, 3, axis=0)
    return Mesh(positions.astype(np.float32), normals.astype(np.float32))


@functools.cache
def _unit_meshes() -> dict[str, Mesh]:
    """Unit box (extents 1), unit cylinder (radius 1, height 1, along z), unit sphere."""
    return {
        kind: _unindexed(unit_primitive(kind), smooth=kind != "box")
        for kind in ("box", "cylinder", "sphere")
    }


def primitive(kind: str, scale_xyz) -> Mesh:
    """A unit primitive scaled per axis (normals corrected for the non-uniform scale)."""
    unit = _unit_meshes()[kind]
    s = np.asarray(scale_xyz, dtype=np.float32)
    normals = unit.normals / s
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return Mesh((unit.positions * s).astype(np.float32), normals.astype(np.float32))


def object_mesh(obj: ObjectDescription) -> Mesh:
    """The object's surface in its own frame (centroid, cylinders along z) [m]: a
    primitive exactly as before, a mesh object's display mesh (graspframe.robot_models.shapes)."""
    if obj.is_mesh:
        return _unindexed(shapes.object_mesh(obj), smooth=True)
    return primitive(obj.shape, unit_scale(obj.shape, obj.dimensions))


def _coal_mesh(shape) -> Mesh:
    primitive_of_shape = geometry_primitive(shape)
    if primitive_of_shape is None:
        raise ValueError(f"cannot draw a {type(shape).__name__} collision shape")
    kind, dimensions = primitive_of_shape
    return primitive(kind, unit_scale(kind, dimensions))


class HandModel:
    """The human hand's collision model, meshed per posture in the palm frame."""

    def __init__(self):
        from graspframe.plugin_system.registry import default_registry
        from graspframe.robot_models.model import CollisionModel

        self.description = default_registry().get_hand("human")
        self.collision = CollisionModel(model_of(self.description))
        meshes = [_coal_mesh(shape) for _, shape, _ in self.collision.shapes()]
        # All shapes' triangles in one array, each shape a slice of it (in shape order),
        # so that posing the hand fills one preallocated array.
        ends = np.cumsum([len(m.positions) for m in meshes])
        self._slices = [
            slice(int(end) - len(m.positions), int(end))
            for m, end in zip(meshes, ends, strict=True)
        ]
        self._positions_shape = np.concatenate([m.positions for m in meshes]).astype(float)
        self._normals_shape = np.concatenate([m.normals for m in meshes]).astype(float)

    def posture_q(self, grasp: HumanGrasp, closure: float) -> dict[str, float]:
        """Driven joints [rad] between the open (0) and the closed (1) posture of `grasp`."""
        preshape = self.description.preshape_for(grasp)
        return {
            name: (1.0 - closure) * preshape.open_q[name] + closure * preshape.closed_q[name]
            for name in preshape.open_q
        }

    def limits(self) -> dict[str, tuple[float, float]]:
        """Joint limits [rad] by name."""
        return {j.name: (j.lower, j.upper) for j in self.description.joints}

    def mesh(self, q_by_joint: dict[str, float]) -> Mesh:
        """The hand's surface in the palm frame for the driven joints q [rad]."""
        self.collision.place(self.description.with_model_followers(q_by_joint))
        T_palm_root = inv_T(self.collision.T_root_frame(PALM_FRAME))
        positions = np.empty_like(self._positions_shape)
        normals = np.empty_like(self._normals_shape)
        for part, (_, _, T_root_shape) in zip(self._slices, self.collision.shapes(), strict=True):
            T_palm_shape = T_palm_root @ T_root_shape
            R_T = T_palm_shape[:3, :3].T
            np.matmul(self._positions_shape[part], R_T, out=positions[part])
            positions[part] += T_palm_shape[:3, 3]
            np.matmul(self._normals_shape[part], R_T, out=normals[part])
        return Mesh(positions.astype(np.float32), normals.astype(np.float32))


def T_palm_object(
    grasp: HumanGrasp, obj: ObjectDescription | None = None
) -> tuple[ObjectDescription, NDArray[np.float64]]:
    """Pose of the grasp's object in the palm frame (inverse of the reference placement)."""
    from graspframe.plugin_system.registry import default_registry
    from graspframe.strategy.reference_poses import reference_placement

    registry = default_registry()
    obj = obj or registry.default_object_for(grasp)
    posture = registry.get_hand("human").preshape_for(grasp)
    return obj, inv_T(reference_placement(obj, posture).T_object_palm)
