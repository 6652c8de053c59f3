"""The hardware abstraction layer: descriptions (what a robot and an object are), drivers
(how to move them in a world) and the classifier's interface. It imports no CLI library
and no simulator; the interfaces of plugin commands and viewers are in
`graspframe.plugin_system`."""

from graspframe.common.moved_modules import moved_name
from graspframe.hal.classifier import (
    Classifier,
    ClassifierOptions,
    ClassifierPicture,
    HumanGraspEstimate,
    Neighbour,
)
from graspframe.hal.descriptions import (
    AdapterShape,
    ArmDescription,
    Coupling,
    DesignObject,
    DriveGains,
    HandDescription,
    HandPreshape,
    JointSpec,
    Mounting,
    joints_by_name,
)
from graspframe.hal.drivers import ArmDriver, Backend, HandDriver, ObjectProbe, World, WorldConfig
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.hal.objects import ObjectDescription

# PluginCommand and Viewer were exported here: they still import, with a DeprecationWarning.
_MOVED_NAMES = {
    "PluginCommand": "graspframe.plugin_system.commands",
    "Viewer": "graspframe.plugin_system.viewer",
}


def __getattr__(name: str) -> object:
    if name in _MOVED_NAMES:
        return moved_name(__name__, name, _MOVED_NAMES[name])
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "AdapterShape",
    "ArmDescription",
    "ArmDriver",
    "Backend",
    "Classifier",
    "ClassifierOptions",
    "ClassifierPicture",
    "Coupling",
    "DesignObject",
    "DriveGains",
    "HandDescription",
    "HandDriver",
    "HandPreshape",
    "HumanGraspEstimate",
    "JointSpec",
    "MountedRobot",
    "Mounting",
    "Neighbour",
    "ObjectDescription",
    "ObjectProbe",
    "World",
    "WorldConfig",
    "joints_by_name",
]
