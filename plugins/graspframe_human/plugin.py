"""Registers the human right hand (the reference hand) with graspframe."""

from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe_human.description import HUMAN


@hookimpl
def graspframe_register_hands(register: Register) -> None:
    register(HUMAN)
