"""Reading URDF models with Pinocchio: joints, limits and links, for checks and kinematics."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

from graspframe.errors import DescriptionError


@dataclass(frozen=True)
class UrdfJoint:
    """A movable joint as Pinocchio reads it: limits [rad] and velocity limit [rad/s]."""

    name: str
    lower: float
    upper: float
    max_velocity: float
    max_effort: float


@dataclass(frozen=True)
class UrdfSummary:
    """What a URDF declares: movable joints (mimic followers included) and link names."""

    joints: dict[str, UrdfJoint]
    links: frozenset[str]


def load_pinocchio_model(path: Path | str, mimic: bool = False):
    """The Pinocchio model of a URDF file; a clear error if it is missing or malformed.

    mimic=True makes <mimic> followers part of their leader joint (reduced configuration).
    """
    import pinocchio as pin

    path = Path(path)
    if not path.is_file():
        raise DescriptionError(f"model file not found: {path}")
    try:
        return pin.buildModelFromUrdf(str(path), mimic)
    except Exception as exc:
        raise DescriptionError(f"Pinocchio cannot load {path.name}: {exc}") from exc


@functools.lru_cache(maxsize=64)
def summarize_urdf(path: Path | str) -> UrdfSummary:
    """Joint limits and link names of a URDF, read by Pinocchio (each follower separately)."""
    import pinocchio as pin

    model = load_pinocchio_model(path, mimic=False)
    joints: dict[str, UrdfJoint] = {}
    for joint_id in range(1, model.njoints):
        joint = model.joints[joint_id]
        if joint.nq != 1:  # only revolute/prismatic joints are actuated in our models
            continue
        iq, iv = joint.idx_q, joint.idx_v
        name = model.names[joint_id]
        joints[name] = UrdfJoint(
            name=name,
            lower=float(model.lowerPositionLimit[iq]),
            upper=float(model.upperPositionLimit[iq]),
            max_velocity=float(model.velocityLimit[iv]),
            max_effort=float(model.effortLimit[iv]),
        )
    links = frozenset(f.name for f in model.frames if f.type == pin.FrameType.BODY)
    return UrdfSummary(joints=joints, links=links)
