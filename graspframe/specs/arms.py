"""An arm spec: its base and flange, driven joints with their motion limits and home
pose, read into an `ArmDescription`; the model is cut at the flange."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from graspframe.hal.descriptions import ArmDescription
from graspframe.model_files.urdf_model import ModelFile, load_model_file
from graspframe.specs.model import read_drive, read_frames, read_joints, read_packages
from graspframe.specs.reader import SpecReader

ARM_KEYS = (
    "kind", "name", "summary", "urdf", "base_link", "flange_link", "home_q", "home_q_deg",
    "packages", "frames", "joints", "drive", "tool_links",
)  # fmt: skip


def read_arm(reader: SpecReader, data: Mapping[str, Any]) -> ArmDescription:
    reader.keys(data, ARM_KEYS, "the spec")
    urdf = reader.resolve(reader.text(data, "urdf", "the spec"), "urdf")
    packages, frames = read_packages(reader, data), read_frames(reader, data)
    flange = reader.text(data, "flange_link", "the spec")
    cut_below = frames[flange].parent if flange in frames else flange
    base_link = reader.text(data, "base_link", "the spec")
    tool_links = data.get("tool_links", [])
    if not isinstance(tool_links, list) or not all(isinstance(n, str) for n in tool_links):
        raise reader.fail("tool_links must be a list of link names")
    model = load_model_file(
        ModelFile(
            urdf,
            packages,
            frames,
            cut_below,
            root_at=base_link,
            root_role="the base link",
            tool_links=tuple(tool_links),
        )
    )
    joints, couplings = read_joints(reader, data, model, need_motion_limits=True)
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
    for joint, value in zip(joints, home_q, strict=True):
        if not joint.contains(value):
            degrees = key == "home_q_deg"
            unit, scale = ("deg", math.degrees) if degrees else ("rad", float)
            raise reader.fail(
                f"{key} puts joint {joint.name!r} at {scale(value):.4g} {unit}, outside its "
                f"limits [{scale(joint.lower):.4g}, {scale(joint.upper):.4g}] {unit} "
                "(from the URDF); give a home pose inside every limit"
            )
    return ArmDescription(
        name=reader.text(data, "name", "the spec"),
        model_path=urdf,
        base_link=base_link,
        flange_link=flange,
        joints=joints,
        home_q=home_q,
        drive=read_drive(reader, data),
        summary=str(data.get("summary", "")),
        packages=packages,
        frames=frames,
        tool_links=tuple(tool_links),
    )
