"""The hardware abstraction layer: descriptions (what a robot is) and drivers (how to move it)."""

from graspframe.hal.classifier import Classifier, ClassifierPicture, HumanGraspEstimate, Neighbour
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
from graspframe.hal.objects import ObjectDescription

__all__ = [
    "AdapterShape",
    "ArmDescription",
    "ArmDriver",
    "Backend",
    "Classifier",
    "ClassifierPicture",
    "Coupling",
    "DesignObject",
    "DriveGains",
    "HandDescription",
    "HandDriver",
    "HandPreshape",
    "HumanGraspEstimate",
    "JointSpec",
    "Mounting",
    "Neighbour",
    "ObjectDescription",
    "ObjectProbe",
    "World",
    "WorldConfig",
]
