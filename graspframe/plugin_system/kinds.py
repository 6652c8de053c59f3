"""The kinds of thing a plugin registers: for each, the hook that registers it and how
the registry checks what it is given (graspframe/plugin_system/registry.py)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from graspframe.hal.classifier import Classifier
from graspframe.hal.depth_camera import DepthCamera
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.hal.drivers import Backend
from graspframe.hal.objects import ObjectDescription
from graspframe.plugin_system.commands import PluginCommand
from graspframe.plugin_system.viewer import Viewer


@dataclass(frozen=True)
class Kind:
    """A kind of registrable thing: the hook that registers it and how to validate it."""

    name: str
    hook: str
    accepts: Callable[[Any], bool]
    expected: str


KINDS: dict[str, Kind] = {
    k.name: k
    for k in (
        Kind(
            "hand",
            "graspframe_register_hands",
            lambda x: isinstance(x, HandDescription),
            "a HandDescription",
        ),
        Kind(
            "arm",
            "graspframe_register_arms",
            lambda x: isinstance(x, ArmDescription),
            "an ArmDescription",
        ),
        Kind(
            "backend",
            "graspframe_register_backends",
            lambda x: isinstance(x, type) and issubclass(x, Backend),
            "a Backend subclass",
        ),
        Kind(
            "classifier",
            "graspframe_register_classifiers",
            lambda x: isinstance(x, type) and issubclass(x, Classifier),
            "a Classifier subclass",
        ),
        Kind(
            "object",
            "graspframe_register_objects",
            lambda x: isinstance(x, ObjectDescription),
            "an ObjectDescription",
        ),
        Kind(
            "camera",
            "graspframe_register_cameras",
            lambda x: isinstance(x, type) and issubclass(x, DepthCamera),
            "a DepthCamera subclass",
        ),
        Kind(
            "viewer",
            "graspframe_register_viewers",
            lambda x: isinstance(x, type) and issubclass(x, Viewer),
            "a Viewer subclass",
        ),
        Kind(
            "command",
            "graspframe_register_commands",
            lambda x: isinstance(x, PluginCommand),
            "a PluginCommand",
        ),
    )
}
