"""An object from a mesh file and its sidecar: a scan registered without Python.

The sidecar of a mesh file `mug.obj` is `mug.toml` beside it (docs/objects.md):

    mass = 0.35                     # [kg]; or density = 700.0 [kg/m^3]: one is required
    grasps = ["large_diameter"]     # optional: else from its shape (hal/shape_grasps.py)
    static_friction = 0.8           # optional, with dynamic_friction (0.8 and 0.6)
    scale = 0.001                   # optional: one factor, or [x, y, z] (mm files)
    collision = "mug_vhacd.stl"     # optional: its convex pieces, else computed
    name = "my_mug"                 # optional: else the mesh file's stem
    summary = "a mug, 80 mm"        # optional: one line
    mesh = "mug.obj"                # optional: else the mesh beside it with its stem

`load_object_file` takes the mesh file or its sidecar. Nothing is guessed: an object
without a mass or a density is an error naming the key to set. Paths in a sidecar are
relative to it; the files are read where they are.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from graspframe.common.errors import DescriptionError
from graspframe.common.files import MESH_SUFFIXES, mesh_file
from graspframe.common.grasps import HumanGrasp
from graspframe.hal.objects import MESH, ObjectDescription
from graspframe.specs.reader import SpecReader

SIDECAR_SUFFIX = ".toml"
OBJECT_KEYS = (
    "name", "summary", "mesh", "collision", "scale", "mass", "density", "static_friction",
    "dynamic_friction", "grasps",
)  # fmt: skip
STATIC_FRICTION, DYNAMIC_FRICTION = 0.8, 0.6  # as the built-in objects (docs/objects.md)


def sidecar_of(mesh: Path) -> Path:
    """The sidecar file of a mesh file: the same name with the suffix .toml."""
    return Path(mesh).with_suffix(SIDECAR_SUFFIX)


def is_object_path(name: str) -> bool:
    """Whether a name given where an object name is expected is a file path (a mesh
    file or a sidecar)."""
    return Path(name).suffix.lower() in (*MESH_SUFFIXES, SIDECAR_SUFFIX)


def _mesh_beside(sidecar: Path, reader: SpecReader) -> Path:
    found = [p for p in sorted(sidecar.parent.glob(f"{sidecar.stem}.*")) if
             p.suffix.lower() in MESH_SUFFIXES]  # fmt: skip
    if len(found) != 1:
        beside = ", ".join(p.name for p in found) or "none"
        raise reader.fail(
            f"set 'mesh' to the mesh file it describes: {len(found)} mesh files named "
            f"{sidecar.stem}.* lie beside it ({beside})"
        )
    return found[0]


def _grasps(reader: SpecReader, value: Any) -> tuple[HumanGrasp, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(g, str) for g in value):
        raise reader.fail(
            f"grasps must be a list of grasp names ({', '.join(g.value for g in HumanGrasp)})"
        )
    try:
        return tuple(HumanGrasp.parse(g) for g in value)
    except DescriptionError:
        raise
    except Exception as exc:
        raise reader.fail(f"grasps: {exc}") from None


def _scale(reader: SpecReader, data: Mapping[str, Any]) -> tuple[float, float, float]:
    value = data.get("scale", 1.0)
    if isinstance(value, list):
        return reader.vector3(value, "scale")
    factor = reader.number(data, "scale", "the sidecar", 1.0)
    return (factor, factor, factor)


def load_object_file(path: Path | str, name: str | None = None) -> ObjectDescription:
    """The object of a mesh file (with its sidecar beside it) or of a sidecar file;
    `name` overrides the sidecar's. DescriptionError, one line, naming what is missing
    or wrong and the key to set."""
    path = Path(path).expanduser()
    sidecar = path if path.suffix.lower() == SIDECAR_SUFFIX else sidecar_of(path)
    if not path.is_file():
        raise DescriptionError(f"object file {path} does not exist")
    if not sidecar.is_file():
        raise DescriptionError(
            f"mesh {path.name} has no sidecar {sidecar.name} beside it: write one with its "
            "mass = <kg> (or density = <kg/m^3>) and, if you like, its grasps"
        )
    reader = SpecReader(sidecar, label="sidecar")
    try:
        data = tomllib.loads(sidecar.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise DescriptionError(f"sidecar {sidecar.name} is not valid TOML: {exc}") from exc
    reader.keys(data, OBJECT_KEYS, "the sidecar")
    if "mass" not in data and "density" not in data:
        raise reader.fail("no mass: set mass = <kg> (or density = <kg/m^3>)")
    if "mesh" in data:
        mesh = reader.resolve(reader.text(data, "mesh", "the sidecar"), "mesh")
    else:
        mesh = path if path != sidecar else _mesh_beside(sidecar, reader)
    mesh = mesh_file(mesh, f"sidecar {sidecar.name}: mesh")
    collision = None
    if "collision" in data:
        collision = reader.resolve(reader.text(data, "collision", "the sidecar"), "collision")
    obj = ObjectDescription(
        name=name or str(data.get("name", mesh.stem)),
        shape=MESH,
        mass=reader.number(data, "mass", "the sidecar") if "mass" in data else 0.0,
        density=reader.number(data, "density", "the sidecar") if "density" in data else None,
        static_friction=reader.number(data, "static_friction", "the sidecar", STATIC_FRICTION),
        dynamic_friction=reader.number(data, "dynamic_friction", "the sidecar", DYNAMIC_FRICTION),
        mesh_path=mesh,
        collision_path=collision,
        scale=_scale(reader, data),
        summary=str(data.get("summary", f"{mesh.name}, from {sidecar.name}")),
    )
    if "grasps" in data:
        return replace(obj, grasps=_grasps(reader, data["grasps"]))
    return obj  # its grasps follow from its shape (ObjectDescription.documented_grasps)
