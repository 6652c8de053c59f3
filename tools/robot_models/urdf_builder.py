"""A small URDF writer for the model generators in this folder.

Each generator (e.g. `python -m tools.robot_models.barrett`) computes a robot's geometry
from the published numbers in docs/robots.md and writes robots/<name>/<name>.urdf.
Collision geometry only: boxes, cylinders and spheres (Pinocchio rejects <capsule>, and
SAPIEN on a CPU-only machine loads collision-only models). Inertias are those of solid
primitives of uniform density, so they are physically consistent with the shapes.

Units: metres, radians, kilograms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

FRAME_LINK_MASS = 1e-3  # [kg] massless marker links (palm frame, flange) get a token mass
FRAME_LINK_INERTIA = 1e-8  # [kg m^2]

Vec3 = tuple[float, float, float]


def _fmt(values) -> str:
    return " ".join(f"{float(v):.6g}" if abs(float(v)) > 1e-12 else "0" for v in values)


def _rpy_to_R(rpy: Vec3) -> np.ndarray:
    # The explicit product, not graspframe.common.transforms.R_from_rpy: the shipped URDFs' inertia
    # digits (round-off in the off-diagonal terms) follow this one.
    r, p, y = rpy
    Rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    Ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    Rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


@dataclass(frozen=True)
class Box:
    size: Vec3
    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)

    @property
    def volume(self) -> float:
        return self.size[0] * self.size[1] * self.size[2]

    def inertia_about_centre(self, mass: float) -> np.ndarray:
        x, y, z = self.size
        return np.diag([y * y + z * z, x * x + z * z, x * x + y * y]) * mass / 12.0

    def xml(self) -> str:
        return f'<box size="{_fmt(self.size)}"/>'


@dataclass(frozen=True)
class Cylinder:
    """Axis along the shape's local z (URDF convention)."""

    radius: float
    length: float
    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)

    @property
    def volume(self) -> float:
        return math.pi * self.radius**2 * self.length

    def inertia_about_centre(self, mass: float) -> np.ndarray:
        r, h = self.radius, self.length
        i_xy = mass * (3 * r * r + h * h) / 12.0
        return np.diag([i_xy, i_xy, mass * r * r / 2.0])

    def xml(self) -> str:
        return f'<cylinder radius="{self.radius:.6g}" length="{self.length:.6g}"/>'


@dataclass(frozen=True)
class Sphere:
    radius: float
    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)

    @property
    def volume(self) -> float:
        return 4.0 / 3.0 * math.pi * self.radius**3

    def inertia_about_centre(self, mass: float) -> np.ndarray:
        return np.eye(3) * 2.0 / 5.0 * mass * self.radius**2

    def xml(self) -> str:
        return f'<sphere radius="{self.radius:.6g}"/>'


Shape = Box | Cylinder | Sphere


def inertial_of(shapes: list[Shape], mass: float) -> tuple[np.ndarray, np.ndarray]:
    """Centre of mass (3,) and inertia (3x3) about it, in the link frame, for solid shapes
    sharing `mass` in proportion to their volume (overlaps counted twice: fine for a model)."""
    volumes = np.array([s.volume for s in shapes])
    masses = mass * volumes / volumes.sum()
    centres = np.array([s.xyz for s in shapes], dtype=float)
    com = (masses[:, None] * centres).sum(axis=0) / mass
    inertia = np.zeros((3, 3))
    for shape, m, c in zip(shapes, masses, centres, strict=True):
        R = _rpy_to_R(shape.rpy)
        d = c - com
        inertia += R @ shape.inertia_about_centre(m) @ R.T + m * (
            d @ d * np.eye(3) - np.outer(d, d)
        )
    return com, inertia


class UrdfBuilder:
    """Collects links and joints, then writes one URDF file."""

    def __init__(self, robot_name: str, comment: str = ""):
        self.robot_name = robot_name
        self.comment = comment
        self._parts: list[str] = []
        self.link_names: list[str] = []
        self.joint_names: list[str] = []

    def link(self, name: str, mass: float = 0.0, shapes: list[Shape] | None = None) -> None:
        """A link; with no shapes it is a frame marker with a token mass."""
        shapes = shapes or []
        if shapes:
            com, inertia = inertial_of(shapes, mass)
        else:
            mass = FRAME_LINK_MASS
            com, inertia = np.zeros(3), np.eye(3) * FRAME_LINK_INERTIA
        lines = [f'  <link name="{name}">']
        lines.append("    <inertial>")
        lines.append(f'      <origin xyz="{_fmt(com)}" rpy="0 0 0"/>')
        lines.append(f'      <mass value="{mass:.6g}"/>')
        lines.append(
            f'      <inertia ixx="{inertia[0, 0]:.6g}" ixy="{inertia[0, 1]:.6g}" '
            f'ixz="{inertia[0, 2]:.6g}" iyy="{inertia[1, 1]:.6g}" iyz="{inertia[1, 2]:.6g}" '
            f'izz="{inertia[2, 2]:.6g}"/>'
        )
        lines.append("    </inertial>")
        for shape in shapes:
            lines.append("    <collision>")
            lines.append(f'      <origin xyz="{_fmt(shape.xyz)}" rpy="{_fmt(shape.rpy)}"/>')
            lines.append(f"      <geometry>{shape.xml()}</geometry>")
            lines.append("    </collision>")
        lines.append("  </link>")
        self._parts.append("\n".join(lines))
        self.link_names.append(name)

    def joint(
        self,
        name: str,
        kind: str,
        parent: str,
        child: str,
        xyz: Vec3 = (0.0, 0.0, 0.0),
        rpy: Vec3 = (0.0, 0.0, 0.0),
        axis: Vec3 = (0.0, 0.0, 1.0),
        lower: float = 0.0,
        upper: float = 0.0,
        effort: float = 0.0,
        velocity: float = 0.0,
        mimic: tuple[str, float, float] | None = None,
    ) -> None:
        """A joint; kind is "revolute" or "fixed". mimic = (leader, multiplier, offset)."""
        lines = [f'  <joint name="{name}" type="{kind}">']
        lines.append(f'    <parent link="{parent}"/>')
        lines.append(f'    <child link="{child}"/>')
        lines.append(f'    <origin xyz="{_fmt(xyz)}" rpy="{_fmt(rpy)}"/>')
        if kind != "fixed":
            lines.append(f'    <axis xyz="{_fmt(axis)}"/>')
            lines.append(
                f'    <limit lower="{lower:.6g}" upper="{upper:.6g}" '
                f'effort="{effort:.6g}" velocity="{velocity:.6g}"/>'
            )
            if mimic is not None:
                leader, multiplier, offset = mimic
                lines.append(
                    f'    <mimic joint="{leader}" multiplier="{multiplier:.6g}" '
                    f'offset="{offset:.6g}"/>'
                )
        lines.append("  </joint>")
        self._parts.append("\n".join(lines))
        self.joint_names.append(name)

    def text(self) -> str:
        header = '<?xml version="1.0"?>\n'
        if self.comment:
            header += f"<!-- {escape(self.comment)} -->\n"
        body = "\n".join(self._parts)
        return f'{header}<robot name="{self.robot_name}">\n{body}\n</robot>\n'

    def write(self, path: Path | str) -> Path:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.text())
        return path
