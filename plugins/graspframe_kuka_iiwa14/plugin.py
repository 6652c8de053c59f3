"""Registers the KUKA LBR iiwa 14 R820 arm."""

from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.hookspecs import Register
from graspframe_kuka_iiwa14.description import arm_description


@hookimpl
def graspframe_register_arms(register: Register) -> None:
    register(arm_description())
