"""Defaults defined once: the plugins a run uses unless told otherwise, and the scene.

The CLI, the runner, the sweep, the vision demo, the plugins and the tools import these
names instead of repeating the values.
"""

from __future__ import annotations

from enum import StrEnum

from graspframe.common.errors import UnknownNameError

DEFAULT_HAND = "karlsruhe"  # `graspframe run` without --hand
DEFAULT_ARM = "kuka"
DEFAULT_CLASSIFIER = "hog_knn"
DEFAULT_BACKEND = "sapien"


class Mount(StrEnum):
    """Where the hand is: on the arm's flange, or alone on a free 6-DOF base (as in the
    method's grasp simulator)."""

    ARM = "arm"
    FLOATING = "floating"

    @classmethod
    def parse(cls, name: str) -> Mount:
        """The mount called `name`, or a one-line error listing the mounts."""
        try:
            return cls(name)
        except ValueError:
            raise UnknownNameError("mount", name, [m.value for m in cls]) from None


class Strategy(StrEnum):
    """How a plan is executed: the published strategy (docs/method.md), or the method
    with the depth camera's corrections (docs/perception.md)."""

    METHOD = "method"
    SERVO = "servo"

    @classmethod
    def parse(cls, name: str) -> Strategy:
        """The strategy called `name`, or a one-line error listing the strategies."""
        try:
            return cls(name)
        except ValueError:
            raise UnknownNameError("strategy", name, [s.value for s in cls]) from None


MOUNT_ARM, MOUNT_FLOATING = Mount.ARM, Mount.FLOATING
MOUNTS = tuple(Mount)

SCENE_FORMAT = "graspframe.scene/1"  # the "format" value of a scene file
SCENE_OBJECT_XY = (0.55, 0.20)  # [m] where the object stands in the world
TABLE_HEIGHT = 0.0  # [m] world z of the table top
TABLE_HALF_SIZE = (0.30, 0.40, 0.02)  # [m] a 60 x 80 cm table top, 4 cm thick
# The held test (graspframe/strategy/held_check.py, docs/method.md#held): the lift and the
# push every grasp, the robot's and the human reference's, is judged by.
LIFT_HEIGHT = 0.05  # [m]
DISTURBANCE_FRACTION = 0.5  # of the object's weight
STRATEGY_METHOD, STRATEGY_SERVO = Strategy.METHOD, Strategy.SERVO
STRATEGIES = tuple(Strategy)
DEFAULT_CAMERA = "simulated"  # the depth camera of the servo strategy
MAX_CAMERA_NOISE = 10.0  # the largest multiple of the camera's noise model accepted
