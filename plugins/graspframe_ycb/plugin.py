"""Scanned objects of the YCB Object and Model Set as mesh objects.

When GRASPFRAME_YCB_DIR names a folder in the YCB layout, every object folder in it
(`<id>_<name>/google_16k/textured.obj`, e.g. `006_mustard_bottle`) whose mass is in
YCB_OBJECTS is registered as `ycb_<id>_<name>`, with `textured_vhacd.stl` beside it as
its convex pieces when present (else they are computed once: graspframe/convex.py).
The files are read where they are; none is copied.

Unset: nothing is registered. A folder that is missing or holds no YCB object, or an
object folder without `google_16k/textured.obj`, fails this plugin with a one-line
error naming the path and what is expected (`graspframe plugins` shows it; the other
plugins work). Object folders of the set whose mass this table does not list are left
out, with one warning naming them.

Masses: B. Calli, A. Walsman, A. Singh, S. Srinivasa, P. Abbeel, A. M. Dollar,
"Benchmarking in Manipulation Research: The YCB Object and Model Set and Benchmarking
Protocols", IEEE Robotics & Automation Magazine 22(3), 2015, Table 1. Friction: static
0.8, dynamic 0.6, as the built-in objects (our choice, not measured). The grasps are the
ones a person would use on each object as it lies on the table (docs/objects.md).
The YCB data is licensed CC BY 4.0 (attribution: Calli et al., above).
"""

from __future__ import annotations

import logging
import os
import re
from dataclasses import dataclass
from pathlib import Path

from graspframe.errors import PluginError
from graspframe.grasps import HumanGrasp
from graspframe.hal.objects import MESH, ObjectDescription
from graspframe.plugins import hookimpl
from graspframe.plugins.hookspecs import Register

log = logging.getLogger(__name__)

YCB_DIR_ENV = "GRASPFRAME_YCB_DIR"
VISUAL_MESH = Path("google_16k") / "textured.obj"
CONVEX_PIECES = Path("google_16k") / "textured_vhacd.stl"
OBJECT_FOLDER = re.compile(r"^\d{3}_[a-z0-9_-]+$")  # the set's folder names, e.g. 025_mug
NAME_PREFIX = "ycb_"
STATIC_FRICTION = 0.8
DYNAMIC_FRICTION = 0.6


@dataclass(frozen=True)
class YcbObject:
    """mass: [kg] (Calli et al. 2015, Table 1); grasps: what a person would use;
    summary: one line."""

    mass: float
    grasps: tuple[HumanGrasp, ...]
    summary: str


YCB_OBJECTS = {
    "005_tomato_soup_can": YcbObject(
        0.349, (HumanGrasp.LARGE_DIAMETER,), "a soup can, diameter 66 mm, 102 mm tall"
    ),
    "006_mustard_bottle": YcbObject(
        0.603, (HumanGrasp.LARGE_DIAMETER,), "a mustard bottle, 95 x 65 mm, 190 mm tall"
    ),
    "011_banana": YcbObject(0.066, (HumanGrasp.PINCH,), "a banana lying on its side, 180 mm"),
    "025_mug": YcbObject(
        0.118, (HumanGrasp.LARGE_DIAMETER,), "a mug with a handle, diameter 80 mm, 81 mm tall"
    ),
    "056_tennis_ball": YcbObject(
        0.058, (HumanGrasp.POWER_SPHERE,), "a tennis ball, diameter 66 mm"
    ),
    "061_foam_brick": YcbObject(0.028, (HumanGrasp.PINCH,), "a foam brick, 50 x 75 x 50 mm"),
}


def object_name(folder_name: str) -> str:
    """The registered name of a YCB object folder, e.g. ycb_006_mustard_bottle."""
    return NAME_PREFIX + folder_name


def ycb_objects(root: Path) -> list[ObjectDescription]:
    """The objects of a YCB-layout folder (see the module docstring); PluginError with a
    one-line message when the folder cannot be used."""
    expected = f"<id>_<name>/{VISUAL_MESH.as_posix()} folders of the YCB object set"
    if not root.is_dir():
        raise PluginError(f"{YCB_DIR_ENV}={root}: no such folder; it should hold {expected}")
    folders = sorted(p for p in root.iterdir() if p.is_dir() and OBJECT_FOLDER.match(p.name))
    if not folders:
        raise PluginError(f"{YCB_DIR_ENV}={root} holds no YCB object; it should hold {expected}")
    objects, unknown = [], []
    for folder in folders:
        mesh_path = folder / VISUAL_MESH
        if not mesh_path.is_file():
            raise PluginError(
                f"YCB object folder {folder} has no {VISUAL_MESH.as_posix()} "
                "(the Google 16k scan of the set's download)"
            )
        facts = YCB_OBJECTS.get(folder.name)
        if facts is None:
            unknown.append(folder.name)
            continue
        pieces = folder / CONVEX_PIECES
        objects.append(
            ObjectDescription(
                name=object_name(folder.name),
                shape=MESH,
                mesh_path=mesh_path,
                collision_path=pieces if pieces.is_file() else None,
                mass=facts.mass,
                static_friction=STATIC_FRICTION,
                dynamic_friction=DYNAMIC_FRICTION,
                grasps=facts.grasps,
                summary=f"YCB {folder.name}: {facts.summary}, {round(1000 * facts.mass)} g",
            )
        )
    if unknown:
        log.warning(
            "%s: %d YCB objects have no mass in graspframe_ycb's table and are not registered: %s",
            YCB_DIR_ENV,
            len(unknown),
            ", ".join(unknown),
        )
    return objects


@hookimpl
def graspframe_register_objects(register: Register) -> None:
    root = os.environ.get(YCB_DIR_ENV, "").strip()
    if not root:
        return  # no YCB folder: nothing to register
    for obj in ycb_objects(Path(root).expanduser()):
        register(obj)
