"""Graspable objects: shape, size, mass and friction, with the object frame at the centroid."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from graspframe.errors import DescriptionError
from graspframe.grasps import HumanGrasp

SHAPES = {
    "box": ("size_x", "size_y", "size_z"),
    "cylinder": ("radius", "length"),  # axis along the object's z
    "sphere": ("radius",),
}


@dataclass(frozen=True)
class ObjectDescription:
    """A rigid object on the table.

    shape: "box", "cylinder" (axis along z) or "sphere".
    dimensions: [m] per shape: box size_x/size_y/size_z, cylinder radius/length,
        sphere radius.
    mass: [kg]; static_friction, dynamic_friction: Coulomb coefficients [-].
    default_for: the human grasps for which this is the default object.
    """

    name: str
    shape: str
    dimensions: Mapping[str, float]
    mass: float
    static_friction: float = 0.8
    dynamic_friction: float = 0.6
    restitution: float = 0.0
    default_for: frozenset[HumanGrasp] = frozenset()
    summary: str = ""
    extras: Mapping[str, object] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise DescriptionError(
                f"object {self.name!r}: unknown shape {self.shape!r}; "
                f"shapes are {', '.join(SHAPES)}"
            )
        needed = set(SHAPES[self.shape])
        if set(self.dimensions) != needed:
            raise DescriptionError(
                f"object {self.name!r}: a {self.shape} needs dimensions "
                f"{', '.join(SHAPES[self.shape])}, got {', '.join(self.dimensions) or 'none'}"
            )
        if any(not v > 0 for v in self.dimensions.values()) or not self.mass > 0:
            raise DescriptionError(f"object {self.name!r}: dimensions and mass must be > 0")

    @property
    def half_extents(self) -> tuple[float, float, float]:
        """[m] half the object's size along its x, y, z (its bounding box about the
        centroid, object frame)."""
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
        """True when any turn about the object's z axis leaves it unchanged."""
        return self.shape in ("cylinder", "sphere")

    @property
    def volume(self) -> float:
        """[m^3]"""
        d = self.dimensions
        if self.shape == "box":
            return d["size_x"] * d["size_y"] * d["size_z"]
        if self.shape == "cylinder":
            return math.pi * d["radius"] ** 2 * d["length"]
        return 4.0 / 3.0 * math.pi * d["radius"] ** 3

    def extent_along(self, n_object) -> float:
        """[m] half-extent of the object along the unit direction n_object (object frame):
        the largest projection of its surface on that direction, measured from the
        centroid."""
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
        """Half the extent along the object's z [m] (distance from centroid to table)."""
        return self.half_extents[2]
