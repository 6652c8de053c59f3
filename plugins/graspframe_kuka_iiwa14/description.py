"""KUKA LBR iiwa 14 R820: joint limits, home pose and drive gains, in SI units.

Joint angles are KUKA's axis values A1..A7 (0 = the arm standing straight up). Numbers
come from KUKA's LBR iiwa specification (the "iiwa spec", docs/robots/kuka_iiwa14.md);
where it is silent the value is OUR ASSUMPTION, marked so. The URDF generator
(tools/robot_models/kuka_iiwa14.py) reads the joint limits from `JOINTS` here, so the model
and the description cannot disagree.
docs/robots/kuka_iiwa14.md tabulates every number.
"""

from __future__ import annotations

import math

from graspframe.hal.descriptions import ArmDescription, DriveGains, JointSpec

NAME = "kuka_iiwa14"
MODEL_FILE = "kuka_iiwa14/kuka_iiwa14.urdf"
BASE_LINK = "iiwa_base"
FLANGE_LINK = "iiwa_flange"
PAYLOAD = 14.0  # [kg] the "14" of the name

# name, limit +- [deg], max speed [deg/s], max torque [N m]: all iiwa spec.
_JOINT_TABLE = (
    ("iiwa_a1", 170.0, 85.0, 320.0),
    ("iiwa_a2", 120.0, 85.0, 320.0),
    ("iiwa_a3", 170.0, 100.0, 176.0),
    ("iiwa_a4", 120.0, 75.0, 176.0),
    ("iiwa_a5", 170.0, 130.0, 110.0),
    ("iiwa_a6", 120.0, 135.0, 40.0),
    ("iiwa_a7", 175.0, 135.0, 40.0),
)
# Assumptions (the iiwa spec gives no acceleration or jerk): full speed in 0.4 s, full
# acceleration in 0.1 s; conservative for trajectory generation.
ACCELERATION_PER_VELOCITY = 2.5  # [1/s]
JERK_PER_ACCELERATION = 10.0  # [1/s]

JOINTS = tuple(
    JointSpec(
        name=name,
        lower=-math.radians(limit_deg),
        upper=math.radians(limit_deg),
        max_velocity=math.radians(speed_deg_s),
        max_effort=torque,
        max_acceleration=ACCELERATION_PER_VELOCITY * math.radians(speed_deg_s),
        max_jerk=JERK_PER_ACCELERATION * ACCELERATION_PER_VELOCITY * math.radians(speed_deg_s),
    )
    for name, limit_deg, speed_deg_s, torque in _JOINT_TABLE
)

# Elbow up, flange pointing straight down 0.50 m in front of the base at 0.40 m height:
# A2 - A4 + A6 = 180 deg (A4 turns about -y, see the generator). Checked in
# tests/test_robot_kuka_iiwa14.py.
HOME_Q_DEG = (0.0, 23.3, 0.0, -100.1, 0.0, 56.6, 0.0)
HOME_Q = tuple(math.radians(q) for q in HOME_Q_DEG)

# Assumption: a stiff, well-damped position drive (the simulator backend may tune it).
# Overdamped: damping ratio about 2.2 (A1) and 1.7 (A2) at home (joint inertia 1.0 and
# 1.7 kg m^2), more on the light wrist joints, so targets are reached without overshoot.
DRIVE = DriveGains(stiffness=5.0e4, damping=1.0e3, force_limit=max(t for *_, t in _JOINT_TABLE))


def arm_description() -> ArmDescription:
    """The iiwa 14 description (needs the generated URDF in robots/kuka_iiwa14/)."""
    from graspframe_robots import model_path

    return ArmDescription(
        name=NAME,
        model_path=model_path(MODEL_FILE),
        base_link=BASE_LINK,
        flange_link=FLANGE_LINK,
        joints=JOINTS,
        home_q=HOME_Q,
        drive=DRIVE,
        payload=PAYLOAD,
        summary="KUKA LBR iiwa 14 R820, 7 DOF lightweight arm, 820 mm reach, 14 kg payload",
    )
