"""Registers the KUKA KR 5 sixx R850 arm."""

from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe_kuka.description import arm_description


@hookimpl
def graspframe_register_arms(register: Register) -> None:
    register(arm_description())
