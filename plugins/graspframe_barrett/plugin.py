"""Registers the Barrett BH8-280 hand with graspframe."""

from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe_barrett.description import BARRETT


@hookimpl
def graspframe_register_hands(register: Register) -> None:
    register(BARRETT)
