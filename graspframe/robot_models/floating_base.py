"""The free-floating mount: a hand on a virtual 6-DOF base instead of an arm.

The method's grasp simulator moves the hand alone, with no arm. graspframe does the same
by mounting the hand on `FLOATING_BASE`, an `ArmDescription` of six virtual joints
(prismatic x, y, z of the base frame, then revolute yaw, pitch, roll) with no collision
shapes: the planner, IK, trajectories and executor run unchanged, and only the hand
touches the table and the object. The virtual drives are stiff, like a rigid wrist.

`T_world_base_for(T_world_palm, T_flange_palm)` places the base so that its home (all
joints at 0) puts the palm at a given pose with the revolute joints at the middle of
their range.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from graspframe.common.transforms import inv_T
from graspframe.hal.arm_datasheet import bundled_arm
from graspframe.hal.descriptions import ArmDescription, DriveGains, HandDescription, JointSpec
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.robot_models.model import model_of

NAME = "floating"
MODEL_FILE = "floating_base/floating_base.urdf"
BASE_LINK = "fb_base"
FLANGE_LINK = "fb_flange"
TRAVEL = 1.0  # [m] of each prismatic joint either side of the base
TURN = math.radians(170.0)  # [rad] of each revolute joint either side of zero
# Motion limits: a brisk hand-held motion (the method's simulator had none: our choice).
LINEAR_SPEED, LINEAR_ACCELERATION, LINEAR_JERK = 0.5, 2.0, 20.0  # [m/s], [m/s^2], [m/s^3]
ANGULAR_SPEED, ANGULAR_ACCELERATION, ANGULAR_JERK = 2.0, 8.0, 80.0  # [rad/s], ...
FORCE_LIMIT = 1.0e4  # [N] or [N m]: the virtual drives never saturate on a grasp
# Stiff (1e5 N/m: 0.1 mm per 10 N) and overdamped, but the palm is held less tightly
# than the stiffness says: the virtual links weigh 1 g each, and the simulator's
# iterations leave the base off its setpoint under a grasp's loads. Measured
# (tests/motion/test_joint_limits.py: the heaviest design object of each built-in hand, from the
# hold through the lift and the pushes, while the setpoint is still): the palm within
# 1.03 mm and 1.08 deg of its setpoint (Barrett, a 0.3 kg ball), 0.36 mm and 0.40 deg
# (Karlsruhe, a 0.44 kg can); heavier loads push it further. An armature of 1 kg
# (1 kg m^2) per joint would hold it within 0.11 mm and 0.002 deg, but it changes which
# marginal grasps hold (docs/robots.md, "Joint limits and drives in the simulator").
# While the base moves, the palm also trails the control cycle's setpoint (0.2 mm at
# 40 mm/s).
PALM_POSITION_ACCURACY = 1.2e-3  # [m] under a design object's loads, setpoint still
PALM_ORIENTATION_ACCURACY = math.radians(1.2)  # [rad]
DRIVE = DriveGains(stiffness=1.0e5, damping=2.0e3, force_limit=FORCE_LIMIT)


def _joint(name: str, linear: bool) -> JointSpec:
    if linear:
        return JointSpec(
            name, -TRAVEL, TRAVEL, LINEAR_SPEED, FORCE_LIMIT, LINEAR_ACCELERATION, LINEAR_JERK
        )
    return JointSpec(
        name, -TURN, TURN, ANGULAR_SPEED, FORCE_LIMIT, ANGULAR_ACCELERATION, ANGULAR_JERK
    )


JOINTS = (
    _joint("fb_x", linear=True),
    _joint("fb_y", linear=True),
    _joint("fb_z", linear=True),
    _joint("fb_yaw", linear=False),
    _joint("fb_pitch", linear=False),
    _joint("fb_roll", linear=False),
)


def floating_base() -> ArmDescription:
    """The virtual base as an arm description (its URDF ships in robots/floating_base/)."""
    return bundled_arm(
        NAME,
        MODEL_FILE,
        (BASE_LINK, FLANGE_LINK),
        JOINTS,
        (0.0,) * len(JOINTS),
        DRIVE,
        "free-floating hand: a virtual 6-DOF base (x, y, z, yaw, pitch, roll)",
    )


def T_world_base_for(
    T_world_palm: NDArray[np.float64], T_flange_palm: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The base pose whose home (every virtual joint at 0) puts the palm at T_world_palm."""
    return np.asarray(T_world_palm, dtype=float) @ inv_T(T_flange_palm)


def mount_floating(
    hand: HandDescription, T_world_palm: NDArray[np.float64]
) -> tuple[MountedRobot, NDArray[np.float64]]:
    """(MountedRobot, T_world_base): `hand` on the floating base, and
    the base pose whose home puts its palm at T_world_palm."""
    from graspframe.robot_models.model import CollisionModel
    from graspframe.robot_models.mounting import mount

    robot = mount(floating_base(), hand)
    # The hand's root sits on the flange, so its root -> palm is flange -> palm.
    T_flange_palm = CollisionModel(model_of(hand)).T_root_frame(hand.palm_frame)
    return robot, T_world_base_for(T_world_palm, T_flange_palm)
