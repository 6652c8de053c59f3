"""A hand spec: its real fingers, fingertips, couplings, preshapes and grasp map, read into
a `HandDescription`; a preshape without a delta gets it from the fingertip frames."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from graspframe.common.errors import DescriptionError
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.hal.descriptions import (
    Coupling,
    DesignObject,
    HandDescription,
    HandPreshape,
)
from graspframe.model_files.urdf_model import ModelFile, load_model_file
from graspframe.robot_models.model import model_of
from graspframe.specs.model import read_drive, read_frames, read_joints, read_packages
from graspframe.specs.mountings import read_mountings
from graspframe.specs.reader import SpecReader

HAND_KEYS = (
    "kind", "name", "summary", "urdf", "mount_link", "root_link", "palm_frame",
    "palm_sensor_link", "mass", "mountings",
    "packages", "frames", "fingers", "fingertips", "joints", "drive", "couplings",
    "preshapes", "grasp_map",
)  # fmt: skip
DRIVE_SYNCHRONISED = "synchronised"
COUPLING_KEYS = ("follower", "leader", "multiplier", "offset", "breakaway_torque")
PRESHAPE_KEYS = (
    "open", "open_deg", "closed", "closed_deg", "delta", "grasp_center", "design_object",
    "roll", "roll_deg", "opposed", "volar_centre_height", "stop_direction",
)  # fmt: skip
DESIGN_KEYS = ("shape", "centre", "radius", "axis", "length")


def _design_object(reader: SpecReader, table: Any, where: str) -> DesignObject:
    if not isinstance(table, dict):
        raise reader.fail(f"{where} must be a table")
    reader.keys(table, DESIGN_KEYS, where)
    shape = reader.text(table, "shape", where)
    if shape not in ("cylinder", "sphere"):
        raise reader.fail(f"{where}: shape must be cylinder or sphere, got {shape!r}")
    centre = reader.vector3(table.get("centre"), f"{where} centre")
    radius = reader.number(table, "radius", where)
    if shape == "sphere":
        return DesignObject("sphere", centre, radius)
    axis = reader.vector3(table.get("axis"), f"{where} axis")
    length = reader.number(table, "length", where)
    return DesignObject("cylinder", centre, radius, axis, length)


def _posture(
    reader: SpecReader, table: Mapping[str, Any], key: str, where: str
) -> dict[str, float]:
    """Joint targets under `key` [rad/m] or `key_deg` [deg]."""
    if (key in table) == (f"{key}_deg" in table):
        raise reader.fail(f"{where} needs [{key}] [rad] or [{key}_deg] [deg], one of them")
    degrees = f"{key}_deg" in table
    values = table[f"{key}_deg" if degrees else key]
    if not isinstance(values, dict):
        raise reader.fail(f"{where} {key} must be a table of joint name = value")
    posture = {}
    for joint in values:
        number = reader.number(values, joint, f"{where} {key}")
        posture[str(joint)] = math.radians(number) if degrees else number
    return posture


def _preshape(reader: SpecReader, name: str, table: Any) -> HandPreshape:
    where = f"[preshapes.{name}]"
    if not isinstance(table, dict):
        raise reader.fail(f"{where} must be a table")
    reader.keys(table, PRESHAPE_KEYS, where)
    opposed = table.get("opposed", [])
    if not isinstance(opposed, list) or not all(
        isinstance(pair, list) and len(pair) == 2 and all(isinstance(f, str) for f in pair)
        for pair in opposed
    ):
        raise reader.fail(f"{where} opposed must be a list of [finger, finger] pairs")

    def optional_vector(key: str) -> tuple[float, float, float] | None:
        if key not in table:
            return None
        return reader.vector3(table[key], f"{where} {key}")

    return HandPreshape(
        name=name,
        open_q=_posture(reader, table, "open", where),
        closed_q=_posture(reader, table, "closed", where),
        delta=reader.number(table, "delta", where) if "delta" in table else math.nan,
        grasp_center=optional_vector("grasp_center"),
        design_object=(
            _design_object(reader, table["design_object"], f"{where} design_object")
            if "design_object" in table
            else None
        ),
        roll=reader.angle(table, "roll", where),
        opposed=tuple((a, b) for a, b in opposed),
        volar_centre_height=(
            reader.number(table, "volar_centre_height", where)
            if "volar_centre_height" in table
            else None
        ),
        stop_direction=optional_vector("stop_direction"),
    )


def _grasp_map(
    reader: SpecReader, data: Mapping[str, Any], preshapes: Mapping[str, HandPreshape]
) -> dict[HumanGrasp, str]:
    table = reader.table(data, "grasp_map", "the spec", required=True)
    grasp_map = {}
    for grasp_name, preshape in table.items():
        try:
            grasp = HumanGrasp.parse(grasp_name)
        except DescriptionError:
            raise
        except Exception as exc:
            raise reader.fail(f"[grasp_map]: {exc}") from None
        if preshape not in preshapes:
            raise reader.fail(
                f"[grasp_map] maps {grasp_name} to {preshape!r}, which is not a preshape; "
                f"preshapes: {', '.join(preshapes)}"
            )
        grasp_map[grasp] = preshape
    return grasp_map


def _links(reader: SpecReader, value: Any, where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise reader.fail(f"{where} must be a non-empty list of link names")
    return tuple(value)


def _couplings(reader: SpecReader, data: Mapping[str, Any]) -> list[Coupling]:
    """The [[couplings]] the hand's controller enforces."""
    couplings = []
    for table in data.get("couplings", []):
        if not isinstance(table, dict):
            raise reader.fail("[[couplings]] entries must be tables")
        reader.keys(table, COUPLING_KEYS, "[[couplings]]")
        couplings.append(
            Coupling(
                reader.text(table, "follower", "[[couplings]]"),
                reader.text(table, "leader", "[[couplings]]"),
                reader.number(table, "multiplier", "[[couplings]]"),
                reader.number(table, "offset", "[[couplings]]", 0.0),
                in_model=False,
                breakaway_torque=(
                    reader.number(table, "breakaway_torque", "[[couplings]]")
                    if "breakaway_torque" in table
                    else None
                ),
            )
        )
    return couplings


def _mount_link(reader: SpecReader, data: Mapping[str, Any]) -> str:
    """`mount_link` (or its older name `root_link`): the link or added frame bolted to
    the arm's flange."""
    if "mount_link" in data and "root_link" in data:
        raise reader.fail("give mount_link or its older name root_link, not both")
    key = "root_link" if "root_link" in data else "mount_link"
    return reader.text(data, key, "the spec")


def read_hand(reader: SpecReader, data: Mapping[str, Any]) -> HandDescription:
    reader.keys(data, HAND_KEYS, "the spec")
    urdf = reader.resolve(reader.text(data, "urdf", "the spec"), "urdf")
    packages, frames = read_packages(reader, data), read_frames(reader, data)
    mount_link = _mount_link(reader, data)
    model = load_model_file(
        ModelFile(urdf, packages, frames, root_at=mount_link, root_role="the mount link")
    )
    joints, couplings = read_joints(reader, data, model, need_motion_limits=False)
    couplings += _couplings(reader, data)
    fingers = {
        finger: _links(reader, links, f"[fingers] {finger}")
        for finger, links in reader.table(data, "fingers", "the spec", required=True).items()
    }
    if PALM not in fingers:
        raise reader.fail(f"[fingers] needs {PALM!r}, the links of the palm")
    tips = reader.table(data, "fingertips", "the spec")
    for finger in tips:
        if finger not in fingers or finger == PALM:
            raise reader.fail(f"[fingertips] names {finger!r}, which is not a finger")
        reader.text(tips, finger, "[fingertips]")  # a frame name
    preshapes = {
        name: _preshape(reader, name, table)
        for name, table in reader.table(data, "preshapes", "the spec", required=True).items()
    }
    hand = HandDescription(
        name=reader.text(data, "name", "the spec"),
        model_path=urdf,
        root_link=mount_link,
        joints=joints,
        palm_frame=reader.text(data, "palm_frame", "the spec"),
        palm_sensor_link=reader.text(data, "palm_sensor_link", "the spec"),
        real_fingers=fingers,
        preshapes=preshapes,
        grasp_map=_grasp_map(reader, data, preshapes),
        drive=read_drive(reader, data, (DRIVE_SYNCHRONISED,)),
        synchronised_closing=_synchronised(reader, data),
        couplings=tuple(couplings),
        mass=reader.number(data, "mass", "the spec", 0.0),
        summary=str(data.get("summary", "")),
        fingertip_frames=dict(tips),
        mountings=read_mountings(reader, data, model),
        packages=packages,
        frames=frames,
    )
    return _with_deltas(reader, hand, tips)


def _synchronised(reader: SpecReader, data: Mapping[str, Any]) -> bool:
    """[drive] synchronised: the controller moves every joint to a posture together."""
    value = reader.table(data, "drive", "the spec", required=True).get(DRIVE_SYNCHRONISED, False)
    if not isinstance(value, bool):
        raise reader.fail(f"[drive] {DRIVE_SYNCHRONISED} must be true or false, got {value!r}")
    return value


def _with_deltas(
    reader: SpecReader, hand: HandDescription, tips: Mapping[str, str]
) -> HandDescription:
    """Preshapes without a delta get it from the model: the fingertip frames' largest
    height above the palm surface in the open preshape."""
    missing = [p for p in hand.preshapes.values() if math.isnan(p.delta)]
    if not missing:
        return hand
    if not tips:
        raise reader.fail(
            f"preshape {missing[0].name!r} has no delta and [fingertips] names no fingertip "
            "frames to compute it from"
        )
    height = fingertip_height(hand, tips)
    preshapes = dict(hand.preshapes)
    for preshape in missing:
        preshapes[preshape.name] = replace(preshape, delta=height(preshape.open_q))
    return replace(hand, preshapes=preshapes)


def fingertip_height(
    hand: HandDescription, tips: Mapping[str, str]
) -> Callable[[Mapping[str, float]], float]:
    """A function: hand joints [rad] -> the largest height [m] of the fingertip frames
    above the palm surface (along the palm frame's +z)."""
    from graspframe.robot_models.model import CollisionModel

    model = CollisionModel(model_of(hand))

    def height(q: Mapping[str, float]) -> float:
        model.place(hand.with_model_followers(dict(q)))
        T_root_palm = model.T_root_frame(hand.palm_frame)
        heights = [
            float((np.linalg.inv(T_root_palm) @ model.T_root_frame(tip))[2, 3])
            for tip in tips.values()
        ]
        return max(heights)

    return height
