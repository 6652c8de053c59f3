"""Scanned objects of the YCB Object and Model Set as mesh objects.

When GRASPFRAME_YCB_DIR names a folder in the YCB layout, every object folder in it
(`<id>_<name>/google_16k/textured.obj`, e.g. `006_mustard_bottle` or `065-a_cups`) is
registered as `ycb_<id>_<name>`, with `textured_vhacd.stl` beside it as its convex
pieces when present (else they are computed once: graspframe/model_files/convex.py). Its mass and
the grasp a person would use come from the set's table (catalogue.py: every object of
the set, Calli et al. 2015); a sidecar beside the mesh (`google_16k/textured.toml`,
graspframe/specs/objects.py) replaces them, or gives them for an object the table has
no mass for (the marbles, the parts of the toy airplane and of the Lego Duplo) or does
not know. The files are read where they are; none is copied.

Unset: nothing is registered. A folder that is missing or holds no YCB object, or an
object folder without `google_16k/textured.obj`, fails this plugin with a one-line
error naming the path and what is expected (`graspframe plugins` shows it; the other
plugins work). An object with no mass from either source is found but not registered
(`NotRegistered`: `graspframe objects` lists it with the key to set, and looking it up
says so).

Friction: static 0.8, dynamic 0.6, as the built-in objects (our choice, not measured).
The YCB data is licensed CC BY 4.0 (attribution: Calli et al., catalogue.py).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from graspframe.common.errors import DescriptionError, PluginError
from graspframe.hal.objects import MESH, ObjectDescription
from graspframe.plugin_system import NotRegistered, hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe.specs.objects import load_object_file, sidecar_of
from graspframe_ycb.catalogue import UNWEIGHED, YCB_OBJECTS

YCB_DIR_ENV = "GRASPFRAME_YCB_DIR"
VISUAL_MESH = Path("google_16k") / "textured.obj"
CONVEX_PIECES = Path("google_16k") / "textured_vhacd.stl"
# The set's folder names, e.g. 025_mug, 065-a_cups, 072-k_toy_airplane.
OBJECT_FOLDER = re.compile(r"^\d{3}(-[a-z])?_[a-z0-9_-]+$")
NAME_PREFIX = "ycb_"
STATIC_FRICTION = 0.8
DYNAMIC_FRICTION = 0.6


def object_name(folder_name: str) -> str:
    """The registered name of a YCB object folder, e.g. ycb_006_mustard_bottle."""
    return NAME_PREFIX + folder_name


def _from_table(folder: Path) -> ObjectDescription:
    facts = YCB_OBJECTS[folder.name]
    pieces = folder / CONVEX_PIECES
    return ObjectDescription(
        name=object_name(folder.name),
        shape=MESH,
        mesh_path=folder / VISUAL_MESH,
        collision_path=pieces if pieces.is_file() else None,
        mass=facts.mass,
        static_friction=STATIC_FRICTION,
        dynamic_friction=DYNAMIC_FRICTION,
        grasps=(facts.grasp,),
        summary=f"YCB {folder.name}: {facts.summary}, {1000 * facts.mass:.4g} g",
    )


def _from_sidecar(folder: Path) -> ObjectDescription:
    obj = load_object_file(folder / VISUAL_MESH, name=object_name(folder.name))
    if obj.collision_path is None and (folder / CONVEX_PIECES).is_file():
        from dataclasses import replace

        obj = replace(obj, collision_path=folder / CONVEX_PIECES)
    return obj


def _unregistered(folder: Path) -> NotRegistered:
    sidecar = sidecar_of(folder / VISUAL_MESH)
    why = (
        "Calli et al. 2015 give no mass for this part of the set"
        if folder.name in UNWEIGHED
        else "it is not in the YCB table (catalogue.py)"
    )
    return NotRegistered(object_name(folder.name), f"no mass: {why}; set mass = <kg> in {sidecar}")


def ycb_objects(root: Path) -> list[ObjectDescription | NotRegistered]:
    """The objects of a YCB-layout folder, and those found without a mass (see the
    module docstring); PluginError with a one-line message when the folder cannot be
    used."""
    expected = f"<id>_<name>/{VISUAL_MESH.as_posix()} folders of the YCB object set"
    if not root.is_dir():
        raise PluginError(f"{YCB_DIR_ENV}={root}: no such folder; it should hold {expected}")
    folders = sorted(p for p in root.iterdir() if p.is_dir() and OBJECT_FOLDER.match(p.name))
    if not folders:
        raise PluginError(f"{YCB_DIR_ENV}={root} holds no YCB object; it should hold {expected}")
    found: list[ObjectDescription | NotRegistered] = []
    for folder in folders:
        if not (folder / VISUAL_MESH).is_file():
            raise PluginError(
                f"YCB object folder {folder} has no {VISUAL_MESH.as_posix()} "
                "(the Google 16k scan of the set's download)"
            )
        if sidecar_of(folder / VISUAL_MESH).is_file():
            try:
                found.append(_from_sidecar(folder))
            except DescriptionError as exc:
                found.append(NotRegistered(object_name(folder.name), str(exc)))
        elif folder.name in YCB_OBJECTS:
            found.append(_from_table(folder))
        else:
            found.append(_unregistered(folder))
    return found


@hookimpl
def graspframe_register_objects(register: Register) -> None:
    root = os.environ.get(YCB_DIR_ENV, "").strip()
    if not root:
        return  # no YCB folder: nothing to register
    for obj in ycb_objects(Path(root).expanduser()):
        register(obj)
