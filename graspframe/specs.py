"""Hand and arm specs: a robot described in a TOML file, no Python needed.

A spec names a URDF as its vendor ships it and adds what graspframe needs and the file
lacks: frames given as offsets from existing links (palm frame, palm pad, fingertips,
flange), the real fingers, drives, couplings and, for a hand, the preshape table.
`load_spec(path)` reads one and returns a `HandDescription` or an `ArmDescription`, the
same object a Python plugin registers; every command that takes a hand or an arm name
also takes a spec path (`graspframe run --hand my_hand.toml`).

Paths in a spec are relative to the spec file; `~` and `${ENV}` are expanded (an unset
variable is an error naming it). Angles are in radians, or in degrees under a key ending
in `_deg`. Every table accepts only its own keys: a misspelt key is an error listing the
accepted ones. The format is documented key by key in docs/specs.md.
"""

from __future__ import annotations

import math
import os
import re
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from graspframe.errors import DescriptionError
from graspframe.grasps import PALM, HumanGrasp
from graspframe.hal.descriptions import (
    ArmDescription,
    Coupling,
    DesignObject,
    DriveGains,
    HandDescription,
    HandPreshape,
    JointSpec,
)
from graspframe.transforms import R_from_rpy, make_T
from graspframe.urdf_model import FrameOffset, UrdfModel, description_model

SPEC_SUFFIX = ".toml"
KINDS = ("hand", "arm")

HAND_KEYS = (
    "kind", "name", "summary", "urdf", "root_link", "palm_frame", "palm_sensor_link", "mass",
    "packages", "frames", "fingers", "fingertips", "joints", "drive", "couplings",
    "preshapes", "grasp_map",
)  # fmt: skip
ARM_KEYS = (
    "kind", "name", "summary", "urdf", "base_link", "flange_link", "home_q", "home_q_deg",
    "payload", "packages", "frames", "joints", "drive",
)  # fmt: skip
FRAME_KEYS = ("parent", "xyz", "rpy", "rpy_deg", "pad")
JOINT_KEYS = ("names", "max_velocity", "max_effort", "max_acceleration", "max_jerk")
DRIVE_KEYS = ("stiffness", "damping", "force_limit")
COUPLING_KEYS = ("follower", "leader", "multiplier", "offset", "breakaway_torque")
PRESHAPE_KEYS = (
    "open", "open_deg", "closed", "closed_deg", "delta", "grasp_center", "design_object",
    "roll", "roll_deg", "opposed", "volar_centre_height", "stop_direction",
)  # fmt: skip
DESIGN_KEYS = ("shape", "centre", "radius", "axis", "length")


def is_spec_path(name: str) -> bool:
    """Whether a name given where a robot name is expected is a spec file path."""
    return name.lower().endswith(SPEC_SUFFIX)


class _Reader:
    """Typed access to one spec's values, with errors that name the spec and the key."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, message: str) -> DescriptionError:
        return DescriptionError(f"spec {self.path.name}: {message}")

    def keys(self, table: Mapping, accepted: tuple[str, ...], where: str) -> None:
        for key in table:
            if key not in accepted:
                raise self.fail(f"unknown key {key!r} in {where}; accepted: {', '.join(accepted)}")

    def table(self, table: Mapping, key: str, where: str, required: bool = False) -> dict:
        value = table.get(key, None)
        if value is None:
            if required:
                raise self.fail(f"{where} needs a [{key}] table")
            return {}
        if not isinstance(value, dict):
            raise self.fail(f"{key!r} in {where} must be a table")
        return value

    def text(self, table: Mapping, key: str, where: str, default: str | None = None) -> str:
        value = table.get(key, default)
        if not isinstance(value, str) or not value:
            raise self.fail(f"{where} needs {key!r}, a non-empty string")
        return value

    def number(self, table: Mapping, key: str, where: str, default: float | None = None) -> float:
        value = table.get(key, default)
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise self.fail(f"{where}: {key!r} must be a finite number, got {value!r}")
        return float(value)

    def vector(self, value: Any, n: int, what: str) -> tuple[float, ...]:
        if (
            not isinstance(value, list)
            or len(value) != n
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        ):
            raise self.fail(f"{what} must be a list of {n} numbers, got {value!r}")
        return tuple(float(v) for v in value)

    def angle(self, table: Mapping, key: str, where: str, default: float = 0.0) -> float:
        """`key` [rad] or `key_deg` [deg]; not both."""
        if key in table and f"{key}_deg" in table:
            raise self.fail(f"{where}: give {key!r} [rad] or {key}_deg [deg], not both")
        if f"{key}_deg" in table:
            return math.radians(self.number(table, f"{key}_deg", where))
        return self.number(table, key, where, default)

    def resolve(self, text: str, what: str) -> Path:
        """A path from the spec: ${ENV} and ~ expanded, relative to the spec's folder."""
        expanded = os.path.expandvars(text)
        unset = re.findall(r"\$\{?(\w+)\}?", expanded)
        if unset:
            raise self.fail(
                f"{what} {text!r} uses the environment variable {unset[0]}, which is not "
                f"set; set it to the folder where you unpacked the vendor's files"
            )
        path = Path(expanded).expanduser()
        return path if path.is_absolute() else (self.path.parent / path).resolve()


def load_spec(path: Path | str) -> HandDescription | ArmDescription:
    """The hand or arm a spec file describes (DescriptionError, one line, for anything
    wrong with it)."""
    path = Path(path).expanduser()
    if not path.is_file():
        raise DescriptionError(f"spec file not found: {path}")
    try:
        data = tomllib.loads(path.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise DescriptionError(f"spec {path.name} is not valid TOML: {exc}") from exc
    reader = _Reader(path)
    kind = data.get("kind")
    if kind not in KINDS:
        raise reader.fail(f"'kind' must be one of {', '.join(KINDS)}, got {kind!r}")
    return _hand(reader, data) if kind == "hand" else _arm(reader, data)


# -- parts shared by hands and arms --------------------------------------------------------


def _packages(reader: _Reader, data: Mapping) -> dict[str, Path]:
    table = reader.table(data, "packages", "the spec")
    return {
        name: reader.resolve(str(folder), f"package {name!r}") for name, folder in table.items()
    }


def _frames(reader: _Reader, data: Mapping) -> dict[str, FrameOffset]:
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
        pad = None if "pad" not in table else reader.vector(table["pad"], 3, f"{where} pad")
        frames[name] = FrameOffset(
            reader.text(table, "parent", where),
            make_T(R_from_rpy(*rpy), xyz),
            pad,  # type: ignore[arg-type]
        )
    return frames


def _drive(reader: _Reader, data: Mapping) -> DriveGains:
    table = reader.table(data, "drive", "the spec", required=True)
    reader.keys(table, DRIVE_KEYS, "[drive]")
    return DriveGains(*(reader.number(table, key, "[drive]") for key in DRIVE_KEYS))


def _movable_joints(model: UrdfModel) -> tuple[list[str], dict[str, dict]]:
    """(movable joint names in file order, name -> {lower, upper, velocity, effort,
    mimic}) of a model."""
    robot = model.root()
    names, info = [], {}
    for joint in robot.findall("joint"):
        if joint.get("type") not in ("revolute", "prismatic", "continuous"):
            continue
        name = joint.get("name", "")
        limit = joint.find("limit")
        values = {} if limit is None else dict(limit.attrib)
        mimic = joint.find("mimic")
        names.append(name)
        info[name] = {
            "lower": float(values.get("lower", -math.pi)),
            "upper": float(values.get("upper", math.pi)),
            "velocity": float(values.get("velocity", 0.0)),
            "effort": float(values.get("effort", 0.0)),
            "mimic": None if mimic is None else mimic.attrib,
        }
    return names, info


def _per_joint(reader: _Reader, table: Mapping, key: str, names: list[str]) -> list[float] | None:
    """A [joints] value given once for all joints or as one number per joint."""
    if key not in table:
        return None
    value = table[key]
    if isinstance(value, list):
        return list(reader.vector(value, len(names), f"[joints] {key} (one per joint)"))
    return [reader.number(table, key, "[joints]")] * len(names)


def _joints(
    reader: _Reader, data: Mapping, model: UrdfModel, need_motion_limits: bool
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


# -- hands ---------------------------------------------------------------------------------


def _design_object(reader: _Reader, table: Any, where: str) -> DesignObject:
    if not isinstance(table, dict):
        raise reader.fail(f"{where} must be a table")
    reader.keys(table, DESIGN_KEYS, where)
    shape = reader.text(table, "shape", where)
    if shape not in ("cylinder", "sphere"):
        raise reader.fail(f"{where}: shape must be cylinder or sphere, got {shape!r}")
    centre = reader.vector(table.get("centre"), 3, f"{where} centre")
    radius = reader.number(table, "radius", where)
    if shape == "sphere":
        return DesignObject("sphere", centre, radius)  # type: ignore[arg-type]
    axis = reader.vector(table.get("axis"), 3, f"{where} axis")
    length = reader.number(table, "length", where)
    return DesignObject("cylinder", centre, radius, axis, length)  # type: ignore[arg-type]


def _posture(reader: _Reader, table: Mapping, key: str, where: str) -> dict[str, float]:
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


def _preshape(reader: _Reader, name: str, table: Any) -> HandPreshape:
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
        return reader.vector(table[key], 3, f"{where} {key}")  # type: ignore[return-value]

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


def _grasp_map(reader: _Reader, data: Mapping, preshapes: Mapping) -> dict[HumanGrasp, str]:
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


def _links(reader: _Reader, value: Any, where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise reader.fail(f"{where} must be a non-empty list of link names")
    return tuple(value)


def _hand(reader: _Reader, data: Mapping) -> HandDescription:
    reader.keys(data, HAND_KEYS, "the spec")
    urdf = reader.resolve(reader.text(data, "urdf", "the spec"), "urdf")
    packages, frames = _packages(reader, data), _frames(reader, data)
    joints, couplings = _joints(
        reader, data, description_model(urdf, packages, frames), need_motion_limits=False
    )
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
    preshapes = {
        name: _preshape(reader, name, table)
        for name, table in reader.table(data, "preshapes", "the spec", required=True).items()
    }
    hand = HandDescription(
        name=reader.text(data, "name", "the spec"),
        model_path=urdf,
        root_link=reader.text(data, "root_link", "the spec"),
        joints=joints,
        palm_frame=reader.text(data, "palm_frame", "the spec"),
        palm_sensor_link=reader.text(data, "palm_sensor_link", "the spec"),
        real_fingers=fingers,
        preshapes=preshapes,
        grasp_map=_grasp_map(reader, data, preshapes),
        drive=_drive(reader, data),
        couplings=tuple(couplings),
        mass=reader.number(data, "mass", "the spec", 0.0),
        summary=str(data.get("summary", "")),
        extras={"fingertip_frames": dict(tips), "spec": str(reader.path)},
        packages=packages,
        frames=frames,
    )
    return _with_deltas(reader, hand)


def _with_deltas(reader: _Reader, hand: HandDescription) -> HandDescription:
    """Preshapes without a delta get it from the model: the fingertip frames' largest
    height above the palm surface in the open preshape."""
    missing = [p for p in hand.preshapes.values() if math.isnan(p.delta)]
    if not missing:
        return hand
    tips = dict(hand.extras.get("fingertip_frames", {}))  # type: ignore[call-overload]
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
    from graspframe.robot_model import CollisionModel

    model = CollisionModel(hand.urdf())

    def height(q: Mapping[str, float]) -> float:
        model.place(hand.with_model_followers(dict(q)))
        T_root_palm = model.T_root_frame(hand.palm_frame)
        heights = [
            float((np.linalg.inv(T_root_palm) @ model.T_root_frame(tip))[2, 3])
            for tip in tips.values()
        ]
        return max(heights)

    return height


# -- arms ----------------------------------------------------------------------------------


def _arm(reader: _Reader, data: Mapping) -> ArmDescription:
    reader.keys(data, ARM_KEYS, "the spec")
    urdf = reader.resolve(reader.text(data, "urdf", "the spec"), "urdf")
    packages, frames = _packages(reader, data), _frames(reader, data)
    flange = reader.text(data, "flange_link", "the spec")
    cut_below = frames[flange].parent if flange in frames else flange
    model = description_model(urdf, packages, frames, cut_below)
    joints, couplings = _joints(reader, data, model, need_motion_limits=True)
    if couplings:
        raise reader.fail(
            f"the arm joints include <mimic> followers ({couplings[0].follower}); name the "
            "driven joints in [joints] names"
        )
    if ("home_q" in data) == ("home_q_deg" in data):
        raise reader.fail("the spec needs home_q [rad] or home_q_deg [deg], one of them")
    key = "home_q_deg" if "home_q_deg" in data else "home_q"
    home_q = reader.vector(data[key], len(joints), f"{key} (one per joint)")
    if key == "home_q_deg":
        home_q = tuple(math.radians(v) for v in home_q)
    return ArmDescription(
        name=reader.text(data, "name", "the spec"),
        model_path=urdf,
        base_link=reader.text(data, "base_link", "the spec"),
        flange_link=flange,
        joints=joints,
        home_q=home_q,
        drive=_drive(reader, data),
        payload=reader.number(data, "payload", "the spec", 0.0),
        summary=str(data.get("summary", "")),
        packages=packages,
        frames=frames,
    )
