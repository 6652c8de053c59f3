"""Registers the KUKA LBR iiwa 14 R820 arm."""

from graspframe.plugins import hookimpl
from graspframe.plugins.hookspecs import Register
from graspframe_kuka_iiwa14.description import arm_description


@hookimpl
def graspframe_register_arms(register: Register) -> None:
    register(arm_description())
