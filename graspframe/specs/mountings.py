"""The `[mountings.NAME]` tables of a hand spec: ways of holding the hand by the arm's
flange other than bolted straight on at its mount link, through an adapter (a plate on
the back of the palm, say), tried in order when no collision-free path exists with the
hand bolted straight on (graspframe/strategy/arm_path.py).

    [mountings.dorsal]
    frame = "leap_dorsal"      # a link or added frame: the flange face, +z into the hand
    mass = 0.05                # [kg] of the adapter
    summary = "a plate on the back of the palm"
    adapter = [{ shape = "box", size = [0.064, 0.064, 0.015], xyz = [0, 0, 0.0075] }]

The adapter's shapes (box `size`, cylinder `radius` and `length` along its z, sphere
`radius`) are placed in the frame's coordinates by `xyz` and `rpy` / `rpy_deg`; the
collision checks and the simulator see them as part of the arm."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from graspframe.common.transforms import R_from_rpy, inv_T, make_T
from graspframe.hal.mountings import AdapterShape, Mounting
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.specs.reader import SpecReader

MOUNTING_KEYS = ("frame", "mass", "summary", "adapter")
SHAPE_KEYS = ("shape", "size", "radius", "length", "xyz", "rpy", "rpy_deg")


def _pose(reader: SpecReader, table: Mapping[str, Any], where: str) -> np.ndarray:
    if "rpy" in table and "rpy_deg" in table:
        raise reader.fail(f"{where}: give rpy [rad] or rpy_deg [deg], not both")
    rpy = reader.vector(table.get("rpy", [0, 0, 0]), 3, f"{where} rpy")
    if "rpy_deg" in table:
        rpy = tuple(math.radians(v) for v in reader.vector(table["rpy_deg"], 3, where))
    return make_T(R_from_rpy(*rpy), reader.vector(table.get("xyz", [0, 0, 0]), 3, f"{where} xyz"))


def _shape(reader: SpecReader, table: Any, where: str, T_root_frame: np.ndarray) -> AdapterShape:
    if not isinstance(table, dict):
        raise reader.fail(f"{where} must be a table")
    reader.keys(table, SHAPE_KEYS, where)
    shape = reader.text(table, "shape", where)
    if shape == "box":
        x, y, z = reader.vector3(table.get("size"), f"{where} size")
        dimensions = {"size_x": x, "size_y": y, "size_z": z}
    elif shape == "cylinder":
        dimensions = {k: reader.number(table, k, where) for k in ("radius", "length")}
    elif shape == "sphere":
        dimensions = {"radius": reader.number(table, "radius", where)}
    else:
        raise reader.fail(f"{where}: shape must be box, cylinder or sphere, got {shape!r}")
    return AdapterShape(shape, dimensions, T_root_frame @ _pose(reader, table, where))


def read_mountings(
    reader: SpecReader, data: Mapping[str, Any], model: UrdfModel
) -> dict[str, Mounting]:
    """The spec's mountings, in order; `model` is the hand's (rooted at its mount link),
    which places each mounting's frame."""
    tables = reader.table(data, "mountings", "the spec")
    if not tables:
        return {}
    from graspframe.robot_models.model import CollisionModel

    placed = CollisionModel(model)
    mountings = {}
    for name, table in tables.items():
        where = f"[mountings.{name}]"
        if not isinstance(table, dict):
            raise reader.fail(f"{where} must be a table")
        reader.keys(table, MOUNTING_KEYS, where)
        frame = reader.text(table, "frame", where)
        if frame not in model.link_names:
            raise reader.fail(f"{where}: frame {frame!r} is not a link or added frame")
        T_root_frame = placed.T_root_frame(frame)
        shapes = table.get("adapter", [])
        if not isinstance(shapes, list):
            raise reader.fail(f"{where} adapter must be a list of shape tables")
        mountings[name] = Mounting(
            T_flange_hand=inv_T(T_root_frame),
            adapter=tuple(
                _shape(reader, shape, f"{where} adapter", T_root_frame) for shape in shapes
            ),
            mass=reader.number(table, "mass", where, 0.0),
            summary=str(table.get("summary", "")),
        )
    return mountings
