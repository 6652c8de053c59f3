"""An arm described from its vendor's data sheet: joint limits and speeds in degrees,
torques, turned into an `ArmDescription` in SI units, with the
assumptions where data sheets are silent (acceleration, jerk, the drive's gains).

The built-in KUKA arms (plugins graspframe_kuka, graspframe_kuka_iiwa14) are described
so; an arm from a spec file (graspframe/specs/) states all of these itself.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from graspframe.hal.descriptions import ArmDescription, DriveGains, JointSpec

# Assumptions (the data sheets give no acceleration or jerk): full speed in 0.4 s, full
# acceleration in 0.1 s; conservative for trajectory generation.
ACCELERATION_PER_VELOCITY = 2.5  # [1/s]
JERK_PER_ACCELERATION = 10.0  # [1/s]
# Assumption: a stiff, well-damped position drive (the simulator backend may tune it);
# each arm's description says the damping ratios it comes to.
DRIVE_STIFFNESS = 5.0e4  # [N m/rad]
DRIVE_DAMPING = 1.0e3  # [N m s/rad]


def datasheet_joints(
    rows: Iterable[tuple[str, float, float, float, float]],
) -> tuple[JointSpec, ...]:
    """The joints of rows (name, lower [deg], upper [deg], max speed [deg/s], max torque
    [N m]), in chain order, with the assumed acceleration and jerk limits."""
    return tuple(
        JointSpec(
            name=name,
            lower=math.radians(lower_deg),
            upper=math.radians(upper_deg),
            max_velocity=math.radians(speed_deg_s),
            max_effort=torque,
            max_acceleration=ACCELERATION_PER_VELOCITY * math.radians(speed_deg_s),
            max_jerk=JERK_PER_ACCELERATION * ACCELERATION_PER_VELOCITY * math.radians(speed_deg_s),
        )
        for name, lower_deg, upper_deg, speed_deg_s, torque in rows
    )


def datasheet_drive(joints: Iterable[JointSpec]) -> DriveGains:
    """The assumed drive, its force limit the largest joint torque."""
    return DriveGains(
        stiffness=DRIVE_STIFFNESS,
        damping=DRIVE_DAMPING,
        force_limit=max(joint.max_effort for joint in joints),
    )


def datasheet_arm(
    name: str,
    model_file: str,
    links: tuple[str, str],
    joints: tuple[JointSpec, ...],
    home_q: tuple[float, ...],
    summary: str,
) -> ArmDescription:
    """The arm whose model is `model_file` of robots/ (graspframe_robots), with its links
    (base, flange), `joints`, home pose [rad] and the assumed drive."""
    return bundled_arm(name, model_file, links, joints, home_q, datasheet_drive(joints), summary)


def bundled_arm(
    name: str,
    model_file: str,
    links: tuple[str, str],
    joints: tuple[JointSpec, ...],
    home_q: tuple[float, ...],
    drive: DriveGains,
    summary: str,
) -> ArmDescription:
    """The arm whose model ships as `model_file` of robots/ (graspframe_robots), with its
    links (base, flange), `joints`, home pose [rad] and `drive`."""
    from graspframe_robots import model_path

    base_link, flange_link = links
    return ArmDescription(
        name=name,
        model_path=model_path(model_file),
        base_link=base_link,
        flange_link=flange_link,
        joints=joints,
        home_q=home_q,
        drive=drive,
        summary=summary,
    )
