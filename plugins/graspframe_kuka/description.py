"""KUKA KR 5 sixx R850: joint limits, home pose and drive gains, in SI units.

Joint angles are KUKA's axis values A1..A6 (0 = the pose of the modified-DH table: upper
arm and forearm stretched forward horizontally). Numbers come from KUKA's KR 5 sixx
specification (the "KR 5 spec", docs/robots/kuka.md); where it is silent the value is OUR
ASSUMPTION, marked so. The URDF
generator (tools/robot_models/kuka.py) reads the joint limits from `JOINTS` here, so the
model and the description cannot disagree. docs/robots/kuka.md tabulates every number.
"""

from __future__ import annotations

import math

from graspframe.hal.arm_datasheet import datasheet_arm, datasheet_joints
from graspframe.hal.descriptions import ArmDescription

NAME = "kuka"
MODEL_FILE = "kuka/kuka.urdf"
BASE_LINK = "kr5_base"
FLANGE_LINK = "kr5_flange"

# name, lower [deg], upper [deg] (KR 5 spec), max speed [deg/s] (KR 5 spec, the
# R650 figures: the R850's are not given), max torque [N m] (assumption: about twice the
# static torque of the stretched arm with 5 kg payload, see docs/robots/kuka.md).
_JOINT_TABLE = (
    ("kr5_a1", -170.0, 170.0, 375.0, 150.0),
    ("kr5_a2", -190.0, 45.0, 300.0, 200.0),
    ("kr5_a3", -119.0, 165.0, 375.0, 100.0),
    ("kr5_a4", -190.0, 190.0, 410.0, 25.0),
    ("kr5_a5", -120.0, 120.0, 410.0, 25.0),
    ("kr5_a6", -358.0, 358.0, 660.0, 15.0),
)
JOINTS = datasheet_joints(_JOINT_TABLE)

# Elbow up, flange pointing straight down 0.50 m in front of the base at 0.38 m height,
# A2 + A3 + A5 = 90 deg (so the flange is vertical). Checked in
# tests/plugins/kuka/test_robot_kuka.py.
HOME_Q_DEG = (0.0, -77.3, 123.6, 0.0, 43.7, 0.0)
HOME_Q = tuple(math.radians(q) for q in HOME_Q_DEG)

# The assumed drive (graspframe.hal.arm_datasheet) is overdamped: damping ratio about
# 1.9 (A1) and 1.6 (A2) at home (joint inertia 1.4 and 1.9 kg m^2), more on the light
# wrist joints, so targets are reached without overshoot.


def arm_description() -> ArmDescription:
    """The KR 5 sixx description (needs the generated URDF in robots/kuka/)."""
    links = (BASE_LINK, FLANGE_LINK)
    summary = "KUKA KR 5 sixx R850, 6 DOF industrial arm, 850 mm reach, 5 kg payload"
    return datasheet_arm(NAME, MODEL_FILE, links, JOINTS, HOME_Q, summary)
