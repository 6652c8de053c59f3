"""The hardware abstraction layer: descriptions (what a robot is) and drivers (how to move it)."""

from graspframe.hal.classifier import Classifier, HumanGraspEstimate, Neighbour
from graspframe.hal.descriptions import (
    ArmDescription,
    Coupling,
    DesignObject,
    DriveGains,
    HandDescription,
    HandPreshape,
    JointSpec,
)
from graspframe.hal.drivers import ArmDriver, Backend, HandDriver, ObjectProbe, World, WorldConfig
from graspframe.hal.objects import ObjectDescription

__all__ = [
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
    "Neighbour",
    "ObjectDescription",
    "ObjectProbe",
    "World",
    "WorldConfig",
]
