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

from graspframe.hal.arm_datasheet import datasheet_arm, datasheet_joints
from graspframe.hal.descriptions import ArmDescription

NAME = "kuka_iiwa14"
MODEL_FILE = "kuka_iiwa14/kuka_iiwa14.urdf"
BASE_LINK = "iiwa_base"
FLANGE_LINK = "iiwa_flange"

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
JOINTS = datasheet_joints(
    (name, -limit_deg, limit_deg, speed_deg_s, torque)
    for name, limit_deg, speed_deg_s, torque in _JOINT_TABLE
)

# Elbow up, flange pointing straight down 0.50 m in front of the base at 0.40 m height:
# A2 - A4 + A6 = 180 deg (A4 turns about -y, see the generator). Checked in
# tests/plugins/kuka_iiwa14/test_robot_kuka_iiwa14.py.
HOME_Q_DEG = (0.0, 23.3, 0.0, -100.1, 0.0, 56.6, 0.0)
HOME_Q = tuple(math.radians(q) for q in HOME_Q_DEG)

# The assumed drive (graspframe.hal.arm_datasheet) is overdamped: damping ratio about
# 2.2 (A1) and 1.7 (A2) at home (joint inertia 1.0 and 1.7 kg m^2), more on the light
# wrist joints, so targets are reached without overshoot.


def arm_description() -> ArmDescription:
    """The iiwa 14 description (needs the generated URDF in robots/kuka_iiwa14/)."""
    links = (BASE_LINK, FLANGE_LINK)
    summary = "KUKA LBR iiwa 14 R820, 7 DOF lightweight arm, 820 mm reach, 14 kg payload"
    return datasheet_arm(NAME, MODEL_FILE, links, JOINTS, HOME_Q, summary)
