"""Registers the Barrett BH8-280 hand with graspframe."""

from graspframe.plugins import hookimpl
from graspframe.plugins.hookspecs import Register
from graspframe_barrett.description import BARRETT


@hookimpl
def graspframe_register_hands(register: Register) -> None:
    register(BARRETT)
