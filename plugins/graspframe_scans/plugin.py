"""Objects from mesh files with their sidecars, registered without Python.

GRASPFRAME_OBJECTS names folders and files, separated by the path separator (`:` on
Linux and macOS, `;` on Windows). Every sidecar found (a `.toml` file beside a mesh
file of the same stem, graspframe/specs/objects.py), in a folder and every folder below
it, is registered as an object: its mass or density, friction and grasps (from its
shape when it names none, docs/objects.md), under its `name`, else the mesh file's stem.
A mesh file named directly registers with its sidecar.

What is found and cannot be registered is kept with its reason (`NotRegistered`:
`graspframe objects` lists it, and looking it up says why): a mesh with no sidecar and
not named by one (its convex pieces, say), a sidecar without a mass, a second object of
the same name. A path that does not exist fails this plugin with a one-line error
(`graspframe plugins` shows it; the other plugins work). The files are read where they
are; none is copied.
"""

from __future__ import annotations

import os
import tomllib
from pathlib import Path

from graspframe.common.errors import DescriptionError, PluginError
from graspframe.common.files import MESH_SUFFIXES
from graspframe.hal.objects import ObjectDescription
from graspframe.plugin_system import NotRegistered, hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe.specs.objects import SIDECAR_SUFFIX, load_object_file, sidecar_of

OBJECTS_ENV = "GRASPFRAME_OBJECTS"


def _is_mesh(path: Path) -> bool:
    return path.is_file() and path.suffix.lower() in MESH_SUFFIXES


def _names_a_mesh(toml: Path) -> bool:
    """A sidecar: a .toml file beside a mesh file of its stem, or naming one (`mesh`)."""
    if any(_is_mesh(p) for p in toml.parent.glob(f"{toml.stem}.*")):
        return True
    try:
        return "mesh" in tomllib.loads(toml.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False


def _sidecars(folder: Path) -> list[Path]:
    """The sidecars in a folder and every folder below it."""
    return sorted(toml for toml in folder.rglob(f"*{SIDECAR_SUFFIX}") if _names_a_mesh(toml))


def _load(path: Path) -> ObjectDescription | NotRegistered:
    try:
        return load_object_file(path)
    except DescriptionError as exc:
        return NotRegistered(path.stem, str(exc))


def objects_in(path: Path) -> list[ObjectDescription | NotRegistered]:
    """The objects of a folder or a mesh file (see the module docstring)."""
    if not path.exists():
        raise PluginError(
            f"{OBJECTS_ENV}: {path} does not exist; give folders of mesh files with their "
            f"sidecars, or mesh files"
        )
    if path.is_file():
        return [_load(path)]
    found = [_load(sidecar) for sidecar in _sidecars(path)]
    used = {
        p.resolve()
        for obj in found
        if isinstance(obj, ObjectDescription)
        for p in (obj.mesh_path, obj.collision_path)
        if p is not None
    }
    for mesh in sorted(p for p in path.rglob("*") if _is_mesh(p)):
        if mesh.resolve() not in used and not sidecar_of(mesh).is_file():
            found.append(
                NotRegistered(
                    mesh.stem,
                    f"mesh {mesh} has no sidecar {sidecar_of(mesh).name} beside it "
                    "(mass = <kg> or density = <kg/m^3>, and its grasps)",
                )
            )
    return found


def registered_objects(paths: list[Path]) -> list[ObjectDescription | NotRegistered]:
    """The objects of every path, a name taken twice kept once (the first)."""
    found: list[ObjectDescription | NotRegistered] = []
    where: dict[str, Path] = {}
    for path in paths:
        for obj in objects_in(path):
            if isinstance(obj, ObjectDescription) and obj.name in where:
                assert obj.mesh_path is not None
                obj = NotRegistered(
                    obj.name,
                    f"{obj.mesh_path} and {where[obj.name]} are both named {obj.name!r}; "
                    "set a different name in one sidecar",
                )
            elif isinstance(obj, ObjectDescription):
                assert obj.mesh_path is not None
                where[obj.name] = obj.mesh_path
            found.append(obj)
    return found


@hookimpl
def graspframe_register_objects(register: Register) -> None:
    value = os.environ.get(OBJECTS_ENV, "").strip()
    if not value:
        return  # no folders named: nothing to register
    paths = [Path(p).expanduser() for p in value.split(os.pathsep) if p.strip()]
    for obj in registered_objects(paths):
        register(obj)
