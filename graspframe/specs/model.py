"""What hand and arm specs say alike about their model: the package folders of its mesh
names, the frames added at offsets, the driven joints (limits from the model, motion
limits from the spec, <mimic> couplings from the model) and the drive gains."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from graspframe.common.transforms import R_from_rpy, make_T
from graspframe.hal.descriptions import Coupling, DriveGains, JointSpec
from graspframe.model_files.coupled_limits import leader_ranges
from graspframe.model_files.urdf_model import FrameOffset, UrdfModel
from graspframe.specs.reader import SpecReader

FRAME_KEYS = ("parent", "xyz", "rpy", "rpy_deg", "pad")
JOINT_KEYS = ("names", "max_velocity", "max_effort", "max_acceleration", "max_jerk")
DRIVE_KEYS = ("stiffness", "damping", "force_limit")  # required
DRIVE_ARMATURE = "armature"  # optional, 0 when left out


def read_packages(reader: SpecReader, data: Mapping[str, Any]) -> dict[str, Path]:
    table = reader.table(data, "packages", "the spec")
    return {
        name: reader.resolve(str(folder), f"package {name!r}") for name, folder in table.items()
    }


def read_frames(reader: SpecReader, data: Mapping[str, Any]) -> dict[str, FrameOffset]:
    frames = {}
    for name, table in reader.table(data, "frames", "the spec").items():
        where = f"[frames.{name}]"
        if not isinstance(table, dict):
            raise reader.fail(f"{where} must be a table")
        reader.keys(table, FRAME_KEYS, where)
        if "rpy" in table and "rpy_deg" in table:
            raise reader.fail(f"{where}: give rpy [rad] or rpy_deg [deg], not both")
        rpy = reader.vector(table.get("rpy", [0, 0, 0]), 3, f"{where} rpy")
        if "rpy_deg" in table:
            rpy = tuple(math.radians(v) for v in reader.vector(table["rpy_deg"], 3, where))
        xyz = reader.vector(table.get("xyz", [0, 0, 0]), 3, f"{where} xyz")
        pad = None if "pad" not in table else reader.vector3(table["pad"], f"{where} pad")
        frames[name] = FrameOffset(
            reader.text(table, "parent", where), make_T(R_from_rpy(*rpy), xyz), pad
        )
    return frames


def read_drive(
    reader: SpecReader, data: Mapping[str, Any], other_keys: tuple[str, ...] = ()
) -> DriveGains:
    """The [drive] table's gains; `other_keys`: further keys the table may hold (read
    by the caller)."""
    table = reader.table(data, "drive", "the spec", required=True)
    reader.keys(table, (*DRIVE_KEYS, DRIVE_ARMATURE, *other_keys), "[drive]")
    stiffness, damping, force_limit = (reader.number(table, k, "[drive]") for k in DRIVE_KEYS)
    armature = reader.number(table, DRIVE_ARMATURE, "[drive]", 0.0)
    return DriveGains(stiffness, damping, force_limit, armature)


def _movable_joints(model: UrdfModel) -> tuple[list[str], dict[str, dict[str, Any]]]:
    """(movable joint names in file order, name -> {lower, upper, velocity, effort,
    mimic}) of a model."""
    robot = model.root()
    names, info = [], {}
    ranges: dict[str, tuple[float, float]] = {}
    for joint in robot.findall("joint"):
        if joint.get("type") not in ("revolute", "prismatic", "continuous"):
            continue
        name = joint.get("name", "")
        limit = joint.find("limit")
        values = {} if limit is None else dict(limit.attrib)
        mimic = joint.find("mimic")
        names.append(name)
        ranges[name] = (float(values.get("lower", -math.pi)), float(values.get("upper", math.pi)))
        info[name] = {
            "lower": ranges[name][0],
            "upper": ranges[name][1],
            "velocity": float(values.get("velocity", 0.0)),
            "effort": float(values.get("effort", 0.0)),
            "mimic": None if mimic is None else mimic.attrib,
        }
    # a leader goes only as far as its followers' limits let it (model_files/coupled_limits)
    for name, (lower, upper) in leader_ranges(ranges, model.mimic_followers).items():
        info[name]["lower"], info[name]["upper"] = lower, upper
    return names, info


def _per_joint(
    reader: SpecReader, table: Mapping[str, Any], key: str, names: list[str]
) -> list[float] | None:
    """A [joints] value given once for all joints or as one number per joint."""
    if key not in table:
        return None
    value = table[key]
    if isinstance(value, list):
        return list(reader.vector(value, len(names), f"[joints] {key} (one per joint)"))
    return [reader.number(table, key, "[joints]")] * len(names)


def read_joints(
    reader: SpecReader, data: Mapping[str, Any], model: UrdfModel, need_motion_limits: bool
) -> tuple[tuple[JointSpec, ...], list[Coupling]]:
    """The driven joints (limits from the model, motion limits from the spec) and the
    model's <mimic> couplings."""
    table = reader.table(data, "joints", "the spec")
    reader.keys(table, JOINT_KEYS, "[joints]")
    movable, info = _movable_joints(model)
    urdf = model.sources[0]
    followers = [n for n in movable if info[n]["mimic"] is not None]
    names = table.get("names", [n for n in movable if n not in followers])
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        raise reader.fail("[joints] names must be a list of joint names")
    for name in names:
        if name not in info:
            raise reader.fail(
                f"[joints] names {name!r}, which is not a movable joint of {urdf.name}; "
                f"it has: {', '.join(movable)}"
            )
    columns = {key: _per_joint(reader, table, key, names) for key in JOINT_KEYS[1:]}
    # key in [joints] -> the URDF <limit> attribute that gives it when the spec does not
    from_urdf = {"max_velocity": "velocity", "max_effort": "effort"}
    joints = []
    for k, name in enumerate(names):
        values = {}
        for key in JOINT_KEYS[1:]:
            given, urdf_key = columns[key], from_urdf.get(key)
            if given is not None:
                values[key] = given[k]
            elif urdf_key is not None and info[name][urdf_key] > 0:
                values[key] = float(info[name][urdf_key])
            elif urdf_key is None and not need_motion_limits:
                values[key] = math.inf  # hand joints: no trajectory generation
            else:
                source = f" and {urdf.name} gives none" if urdf_key else ""
                raise reader.fail(f"joint {name!r} needs {key} in [joints]{source}")
        joints.append(JointSpec(name, info[name]["lower"], info[name]["upper"], **values))
    couplings = [
        Coupling(
            name,
            info[name]["mimic"]["joint"],
            float(info[name]["mimic"].get("multiplier", 1.0)),
            float(info[name]["mimic"].get("offset", 0.0)),
            in_model=True,
        )
        for name in followers
    ]
    return tuple(joints), couplings
