"""Shapes converted once: primitives and collision geometries as triangle meshes (trimesh)
and as coal collision shapes; an object's display mesh and its collision pieces.

A primitive is a shape name and its dimensions [m] in `ObjectDescription`'s convention:
"box" (size_x, size_y, size_z: full sizes), "cylinder" (radius, length; axis along its z)
or "sphere" (radius), centred on its own frame. A collision geometry is a coal shape as
Pinocchio's geometry model holds it (Box, Cylinder, Sphere, Capsule, Cone, centred on
their frame; Convex as its hull; any other kind is meshed as its local bounding box).

An object (ObjectDescription) has one display mesh, `object_mesh` (a mesh object's
visual mesh, e.g. the textured scan; a primitive's surface), and one collision geometry,
`object_collision_meshes` (a mesh object's convex pieces, the ones the simulator, the
collision checker and the planner use; a primitive's surface), both in the object frame.

The renderer, the rerun recording, the snapshot pictures, the hand geometry and the
hand drawings all take their meshes from here.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
import trimesh
from numpy.typing import NDArray

if TYPE_CHECKING:
    from graspframe.hal.objects import ObjectDescription

CYLINDER_SECTIONS = 20  # sides of a meshed cylinder, cone or capsule
SPHERE_SUBDIVISIONS = 2  # icosphere subdivisions of a meshed sphere


@functools.cache
def _unit_mesh(shape: str, sections: int) -> trimesh.Trimesh:
    if shape == "box":
        return trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    if shape == "cylinder":
        return trimesh.creation.cylinder(radius=1.0, height=1.0, sections=sections)
    if shape == "sphere":
        return trimesh.creation.icosphere(subdivisions=SPHERE_SUBDIVISIONS, radius=1.0)
    raise ValueError(f"unknown primitive {shape!r}; primitives are box, cylinder, sphere")


def unit_primitive(shape: str, sections: int = CYLINDER_SECTIONS) -> trimesh.Trimesh:
    """The unit primitive: a box of extents 1, a cylinder of radius 1 and length 1 along
    z, a sphere of radius 1; `unit_scale` stretches it to a size."""
    return _unit_mesh(shape, sections).copy()


def unit_scale(shape: str, dimensions: Mapping[str, float]) -> NDArray[np.float64]:
    """Per-axis scale (3,) taking the unit primitive to `dimensions` [m]."""
    d = dimensions
    if shape == "box":
        return np.array([d["size_x"], d["size_y"], d["size_z"]], dtype=float)
    if shape == "cylinder":
        return np.array([d["radius"], d["radius"], d["length"]], dtype=float)
    if shape == "sphere":
        return np.full(3, float(d["radius"]))
    raise ValueError(f"unknown primitive {shape!r}; primitives are box, cylinder, sphere")


def primitive_mesh(
    shape: str, dimensions: Mapping[str, float], sections: int = CYLINDER_SECTIONS
) -> trimesh.Trimesh:
    """The primitive's surface in its own frame [m]; a cylinder has `sections` sides."""
    unit = _unit_mesh(shape, sections)
    return trimesh.Trimesh(unit.vertices * unit_scale(shape, dimensions), unit.faces, process=False)


def geometry_primitive(geometry) -> tuple[str, dict[str, float]] | None:
    """(shape, dimensions [m]) of a coal Box, Cylinder or Sphere; None for other kinds."""
    kind = type(geometry).__name__
    if kind == "Box":
        sx, sy, sz = (2.0 * float(h) for h in np.asarray(geometry.halfSide))
        return "box", {"size_x": sx, "size_y": sy, "size_z": sz}
    if kind == "Cylinder":
        return "cylinder", {
            "radius": float(geometry.radius),
            "length": 2.0 * float(geometry.halfLength),
        }
    if kind == "Sphere":
        return "sphere", {"radius": float(geometry.radius)}
    return None


def convex_points(geometry) -> NDArray[np.float64]:
    """(n, 3) [m] the vertices of a coal Convex, in its own frame."""
    return np.asarray(geometry.points(), dtype=float).reshape(-1, 3)


def geometry_mesh(geometry, sections: int = CYLINDER_SECTIONS) -> trimesh.Trimesh | None:
    """The surface of a coal collision geometry in its own frame [m]. Capsules and cones
    are meshed, a convex piece is its hull; other kinds as their local bounding box;
    None when even that is not available."""
    primitive = geometry_primitive(geometry)
    if primitive is not None:
        return primitive_mesh(*primitive, sections=sections)
    kind = type(geometry).__name__
    if kind == "Convex":
        return trimesh.convex.convex_hull(convex_points(geometry))
    if kind == "Capsule":
        return trimesh.creation.capsule(
            height=2.0 * float(geometry.halfLength),
            radius=float(geometry.radius),
            count=[sections, sections],
        )
    if kind == "Cone":
        h = float(geometry.halfLength)
        cone = trimesh.creation.cone(
            radius=float(geometry.radius), height=2.0 * h, sections=sections
        )
        cone.apply_translation([0.0, 0.0, -h])  # trimesh puts the base at z = 0
        return cone
    try:
        geometry.computeLocalAABB()
        low = np.asarray(geometry.aabb_local.min_, dtype=float)
        high = np.asarray(geometry.aabb_local.max_, dtype=float)
    except Exception:  # an exotic geometry: no mesh rather than failing the caller
        return None
    if not (np.all(np.isfinite(low)) and np.all(np.isfinite(high))):
        return None
    box = trimesh.creation.box(extents=high - low)
    box.apply_translation((high + low) / 2)
    return box


def coal_geometry(shape: str, dimensions: Mapping[str, float]):
    """The coal collision shape of a primitive, centred on its frame (cylinder axis = z)."""
    import coal

    d = dimensions
    if shape == "box":
        return coal.Box(d["size_x"], d["size_y"], d["size_z"])
    if shape == "cylinder":
        return coal.Cylinder(d["radius"], d["length"])
    if shape == "sphere":
        return coal.Sphere(d["radius"])
    raise ValueError(f"unknown primitive {shape!r}; primitives are box, cylinder, sphere")


def coal_convex(mesh: trimesh.Trimesh):
    """A closed convex mesh (e.g. a convex piece) as a coal Convex with exactly its
    vertices and triangles, in the mesh's frame."""
    import coal

    points = coal.StdVec_Vec3s()
    for p in np.asarray(mesh.vertices, dtype=float):
        points.append(p)
    triangles = coal.StdVec_Triangle()
    for a, b, c in np.asarray(mesh.faces):
        triangles.append(coal.Triangle(int(a), int(b), int(c)))
    return coal.Convex(points, triangles)


def object_mesh(obj: ObjectDescription) -> trimesh.Trimesh:
    """The object's display mesh in the object frame [m]: a mesh object's visual mesh
    (its mesh file, recentred and turned to its rest pose), a primitive's surface. A new
    mesh each call (the caller may change it)."""
    if obj.is_mesh:
        from graspframe.model_files.mesh_geometry import display_mesh

        assert obj.mesh_path is not None
        return display_mesh(obj.mesh_geometry(), obj.mesh_path, obj.scale)
    return primitive_mesh(obj.shape, obj.dimensions)


def textured_object_mesh(obj: ObjectDescription):
    """(display mesh in the object frame, RGBA vertex colours (n, 4) or None): a mesh
    object's visual mesh with the colours of its texture when it has one (a texture is
    decoded: slower than `object_mesh`); a primitive's surface and None."""
    if obj.is_mesh:
        from graspframe.model_files.mesh_geometry import textured_display_mesh

        assert obj.mesh_path is not None
        return textured_display_mesh(obj.mesh_geometry(), obj.mesh_path, obj.scale)
    return primitive_mesh(obj.shape, obj.dimensions), None


def object_collision_meshes(obj: ObjectDescription) -> tuple[trimesh.Trimesh, ...]:
    """The object's collision geometry in the object frame [m]: a mesh object's convex
    pieces (the simulator's, the collision checker's, the planner's), a primitive's
    surface (one mesh; the simulator and the checker use the exact primitive)."""
    if obj.is_mesh:
        return tuple(piece.copy() for piece in obj.mesh_geometry().pieces)
    return (primitive_mesh(obj.shape, obj.dimensions),)


def object_coal_geometries(obj: ObjectDescription) -> list:
    """The object's coal collision shapes, each placed at the object frame: a mesh
    object's convex pieces as coal Convex shapes, a primitive as its coal primitive."""
    if obj.is_mesh:
        return [coal_convex(piece) for piece in obj.mesh_geometry().pieces]
    return [coal_geometry(obj.shape, obj.dimensions)]


RING_SECTIONS = 12  # sides of a cylinder's mesh in local_shape_points: rims at 30 deg


def local_shape_points(shape) -> np.ndarray:
    """Points bounding a collision shape (its mesh's vertices), in its own frame. A
    sphere gives its extreme points along the frame's axes instead (placed, exact for the
    lowest point along any axis of the frame it is placed in; their mean is its centre).
    Meshing is the slow part: CollisionModel.local_points keeps them per shape."""
    if type(shape).__name__ == "Sphere":
        return np.concatenate([np.eye(3), -np.eye(3)]) * shape.radius
    mesh = geometry_mesh(shape, sections=RING_SECTIONS)
    if mesh is None:
        return np.zeros((1, 3))
    return np.asarray(mesh.vertices, dtype=float)
