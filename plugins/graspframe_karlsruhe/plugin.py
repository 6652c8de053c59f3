"""Registers the Karlsruhe humanoid hand with graspframe."""

from __future__ import annotations

from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe_karlsruhe.description import KARLSRUHE_HAND


@hookimpl
def graspframe_register_hands(register: Register) -> None:
    register(KARLSRUHE_HAND)
