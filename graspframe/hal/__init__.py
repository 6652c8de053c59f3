"""The hardware abstraction layer: descriptions (what a robot is) and drivers (how to move
it), and the interfaces of the other things plugins provide (classifiers, viewers,
commands)."""

from graspframe.hal.classifier import (
    Classifier,
    ClassifierOptions,
    ClassifierPicture,
    HumanGraspEstimate,
    Neighbour,
)
from graspframe.hal.commands import PluginCommand
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
from graspframe.hal.viewer import Viewer

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
    "PluginCommand",
    "Viewer",
    "World",
    "WorldConfig",
    "joints_by_name",
]
