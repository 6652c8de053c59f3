"""The hardware abstraction layer: descriptions (what a robot is) and drivers (how to move it)."""

from graspframe.hal.classifier import Classifier, HumanGraspEstimate, Neighbour
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
)
from graspframe.hal.drivers import ArmDriver, Backend, HandDriver, ObjectProbe, World, WorldConfig
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.hal.objects import ObjectDescription

__all__ = [
    "AdapterShape",
    "ArmDescription",
    "ArmDriver",
    "Backend",
    "Classifier",
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
]
