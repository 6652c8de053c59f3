"""Motion: palm-pose inverse kinematics (placo) and jerk-limited trajectories (ruckig).

Core code: no simulator import. Joint values are in [rad], times in [s].
"""

from graspframe.motion.ik import (
    ACCEPT_ORIENTATION_ERROR,
    ACCEPT_POSITION_ERROR,
    IkSolution,
    IkSolver,
    UnreachableError,
)
from graspframe.motion.trajectory import (
    JointLimits,
    JointTrajectory,
    OnlineTrajectory,
    plan_joint_trajectory,
)

__all__ = [
    "ACCEPT_ORIENTATION_ERROR",
    "ACCEPT_POSITION_ERROR",
    "IkSolution",
    "IkSolver",
    "JointLimits",
    "JointTrajectory",
    "OnlineTrajectory",
    "UnreachableError",
    "plan_joint_trajectory",
]
