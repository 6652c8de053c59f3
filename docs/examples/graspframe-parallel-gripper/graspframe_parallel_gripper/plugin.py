"""Registers the parallel gripper with graspframe (named by the entry point in pyproject)."""

from graspframe.plugins import hookimpl
from graspframe.plugins.hookspecs import Register
from graspframe_parallel_gripper.description import PARALLEL_GRIPPER


@hookimpl
def graspframe_register_hands(register: Register) -> None:
    register(PARALLEL_GRIPPER)
