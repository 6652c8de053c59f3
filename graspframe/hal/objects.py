"""Graspable objects: shape, size, mass and friction, with the object frame at the centroid.

An object is a primitive (box, cylinder, sphere, given by its dimensions) or a mesh (a
mesh file, e.g. a scan, with its mass or density). A mesh object's geometry (its frame at
the centroid, rest pose, convex pieces, volume, inertia) is computed from the file once
per process by graspframe/model_files/mesh_geometry.py, when it is first needed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from graspframe.common.defaults import TABLE_HEIGHT
from graspframe.common.errors import DescriptionError
from graspframe.common.files import MESH_SUFFIXES, mesh_file
from graspframe.common.grasps import HumanGrasp

if TYPE_CHECKING:
    from graspframe.model_files.mesh_geometry import MeshGeometry

SHAPES = {
    "box": ("size_x", "size_y", "size_z"),
    "cylinder": ("radius", "length"),  # axis along the object's z
    "sphere": ("radius",),
}
MESH = "mesh"


@dataclass(frozen=True)
class ObjectDescription:
    """A rigid object on the table.

    shape: "box", "cylinder" (axis along z), "sphere" or "mesh".
    dimensions: [m] per primitive shape: box size_x/size_y/size_z, cylinder
        radius/length, sphere radius; none for a mesh.
    mass: [kg]; a mesh may give its density instead (0, the default, then: density times
        the volume of its convex pieces, computed when the description is made).
    static_friction, dynamic_friction: Coulomb coefficients [-].
    default_for: the human grasps for which this is the default object.
    grasps: the grasps a person would use on this object, what `graspframe evaluate
        --objects` runs (empty: those it is the default for).
    mesh_path: a mesh object's mesh file (OBJ, STL, GLB, PLY): its visual mesh, in
        metres after `scale`, z up as it stands (see graspframe/model_files/mesh_geometry.py for
        the object frame and the rest pose).
    collision_path: optional file of the mesh's convex pieces (e.g. a V-HACD
        decomposition, its connected parts the pieces); without it they are computed
        (graspframe/model_files/convex.py).
    scale: per-axis factor on the mesh files' coordinates (e.g. 0.001 for millimetres).
    density: [kg/m^3] of a mesh object given without its mass.
    """

    name: str
    shape: str
    dimensions: Mapping[str, float] = field(default_factory=dict)
    mass: float = 0.0
    static_friction: float = 0.8
    dynamic_friction: float = 0.6
    restitution: float = 0.0
    default_for: frozenset[HumanGrasp] = frozenset()
    summary: str = ""
    extras: Mapping[str, object] = field(default_factory=dict)
    grasps: tuple[HumanGrasp, ...] = ()
    mesh_path: Path | None = None
    collision_path: Path | None = None
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    density: float | None = None

    def __post_init__(self) -> None:
        if self.shape == MESH:
            self._check_mesh()
            return
        if self.shape not in SHAPES:
            raise DescriptionError(
                f"object {self.name!r}: unknown shape {self.shape!r}; "
                f"shapes are {', '.join(SHAPES)}, {MESH}"
            )
        needed = set(SHAPES[self.shape])
        if set(self.dimensions) != needed:
            raise DescriptionError(
                f"object {self.name!r}: a {self.shape} needs dimensions "
                f"{', '.join(SHAPES[self.shape])}, got {', '.join(self.dimensions) or 'none'}"
            )
        if any(not v > 0 for v in self.dimensions.values()) or not self.mass > 0:
            raise DescriptionError(f"object {self.name!r}: dimensions and mass must be > 0")
        if self.mesh_path is not None or self.collision_path is not None or self.density:
            raise DescriptionError(
                f"object {self.name!r}: mesh_path, collision_path and density are for "
                f"shape {MESH!r}, not a {self.shape}"
            )

    def _check_mesh(self) -> None:
        """A mesh object's inputs, checked without reading the mesh (unless only the
        density is given: the mass then needs the volume)."""
        what = f"object {self.name!r}"
        if self.mesh_path is None:
            raise DescriptionError(
                f"{what}: a mesh object needs mesh_path, a {'/'.join(MESH_SUFFIXES)} file"
            )
        for label in ("mesh_path", "collision_path"):
            value = getattr(self, label)
            if value is None:
                continue
            path = mesh_file(value, f"{what}: {label}")
            object.__setattr__(self, label, path)
        if self.dimensions:
            raise DescriptionError(
                f"{what}: a mesh object takes no dimensions (its size is its mesh's), "
                f"got {', '.join(self.dimensions)}"
            )
        scale = tuple(float(s) for s in np.asarray(self.scale, dtype=float).reshape(-1))
        if len(scale) != 3 or not all(math.isfinite(s) and s > 0 for s in scale):
            raise DescriptionError(
                f"{what}: scale must be three numbers > 0 (x, y, z), got {self.scale}"
            )
        object.__setattr__(self, "scale", scale)
        mass_given = math.isfinite(self.mass) and self.mass > 0
        density_given = self.density is not None and math.isfinite(self.density)
        if (self.mass and not mass_given) or (
            self.density is not None and not (density_given and self.density > 0)
        ):
            raise DescriptionError(
                f"{what}: mass [kg] and density [kg/m^3] must be > 0, got mass "
                f"{self.mass}, density {self.density}"
            )
        if not mass_given and not density_given:
            raise DescriptionError(
                f"{what}: a mesh object needs its mass [kg] or its density [kg/m^3]"
            )
        if density_given:
            assert self.density is not None
            from_density = self.density * self.mesh_geometry().volume
            if mass_given and not math.isclose(self.mass, from_density, rel_tol=1e-6):
                raise DescriptionError(
                    f"{what}: give its mass or its density, not both: mass {self.mass} kg "
                    f"but density x volume = {from_density:.6g} kg"
                )
            object.__setattr__(self, "mass", from_density)

    @property
    def is_mesh(self) -> bool:
        return self.shape == MESH

    def mesh_geometry(self) -> MeshGeometry:
        """A mesh object's geometry (graspframe/model_files/mesh_geometry.py; computed once per
        process). DescriptionError for a primitive, or a mesh file that cannot be used."""
        if not self.is_mesh:
            raise DescriptionError(f"object {self.name!r} is a {self.shape}, not a mesh")
        from graspframe.model_files.mesh_geometry import mesh_geometry

        assert self.mesh_path is not None
        return mesh_geometry(self.mesh_path, self.collision_path, self.scale)

    @property
    def inertia(self) -> np.ndarray:
        """3x3 inertia about the centroid in the object frame [kg m^2], at uniform density
        (the primitives' from their shape, a mesh's from its convex pieces' union)."""
        if self.is_mesh:
            return self.mass * self.mesh_geometry().inertia_per_mass
        return self.mass * _primitive_inertia_per_mass(self.shape, self.dimensions)

    def documented_grasps(self) -> tuple[HumanGrasp, ...]:
        """The grasps a person would use on this object: `grasps`, else the grasps it is
        the default object for (in the order of HumanGrasp), else the one its measured
        shape calls for (graspframe/hal/shape_grasps.py, docs/objects.md)."""
        if self.grasps:
            return self.grasps
        if self.default_for:
            return tuple(g for g in HumanGrasp if g in self.default_for)
        from graspframe.hal.shape_grasps import grasp_from_shape

        return (grasp_from_shape(self)[0],)

    @property
    def half_extents(self) -> tuple[float, float, float]:
        """[m] half the object's size along its x, y, z (object frame): a primitive's
        bounding box is centred on the centroid; a mesh's (of its convex pieces) need not
        be."""
        if self.is_mesh:
            low, high = self.mesh_geometry().bounds
            x, y, z = (float(v) for v in (high - low) / 2)
            return (x, y, z)
        d = self.dimensions
        if self.shape == "box":
            return (d["size_x"] / 2, d["size_y"] / 2, d["size_z"] / 2)
        if self.shape == "cylinder":
            return (d["radius"], d["radius"], d["length"] / 2)
        return (d["radius"],) * 3

    @property
    def largest_dimension(self) -> float:
        """[m] the largest extent of the object."""
        return 2 * max(self.half_extents)

    @property
    def symmetric_about_z(self) -> bool:
        """True when any turn about the object's z axis leaves it unchanged (a mesh:
        within the tolerance of graspframe/model_files/mesh_geometry.py)."""
        if self.is_mesh:
            return self.mesh_geometry().symmetric_about_z
        return self.shape in ("cylinder", "sphere")

    @property
    def volume(self) -> float:
        """[m^3] (a mesh: of the union of its convex pieces)"""
        if self.is_mesh:
            return self.mesh_geometry().volume
        d = self.dimensions
        if self.shape == "box":
            return d["size_x"] * d["size_y"] * d["size_z"]
        if self.shape == "cylinder":
            return math.pi * d["radius"] ** 2 * d["length"]
        return 4.0 / 3.0 * math.pi * d["radius"] ** 3

    def extent_along(self, n_object: ArrayLike) -> float:
        """[m] half-extent of the object along the unit direction n_object (object frame):
        the largest projection of its surface on that direction, measured from the
        centroid (a mesh: of its convex pieces; a primitive reaches as far along -n)."""
        if self.is_mesh:
            return self.mesh_geometry().extent_along(n_object)
        n = np.abs(np.asarray(n_object, dtype=float))
        n = n / np.linalg.norm(n)
        radius, _, half_length = self.half_extents
        if self.shape == "box":
            return float(n @ self.half_extents)
        if self.shape == "cylinder":
            return float(n[2] * half_length + math.sqrt(max(0.0, 1 - n[2] ** 2)) * radius)
        return radius

    @property
    def half_height(self) -> float:
        """[m] height of the centroid above the table the object rests on (a primitive:
        half its extent along z)."""
        if self.is_mesh:
            return float(-self.mesh_geometry().bounds[0, 2])
        return self.half_extents[2]

    def T_world_standing(
        self, xy: tuple[float, float] = (0.0, 0.0), table_height: float = TABLE_HEIGHT
    ) -> NDArray[np.float64]:
        """The object standing upright on the table top at world (x, y) [m]: its pose in
        the world, where every scene, check and reference puts an object."""
        T = np.eye(4)
        T[:3, 3] = (xy[0], xy[1], table_height + self.half_height)
        return T


def _primitive_inertia_per_mass(shape: str, d: Mapping[str, float]) -> np.ndarray:
    """3x3 inertia per kg [m^2] of a uniform box, cylinder (axis z) or sphere."""
    if shape == "box":
        x2, y2, z2 = d["size_x"] ** 2, d["size_y"] ** 2, d["size_z"] ** 2
        return np.diag([y2 + z2, x2 + z2, x2 + y2]) / 12.0
    if shape == "cylinder":
        r2, h2 = d["radius"] ** 2, d["length"] ** 2
        return np.diag([(3 * r2 + h2) / 12.0, (3 * r2 + h2) / 12.0, r2 / 2.0])
    return np.eye(3) * 0.4 * d["radius"] ** 2
