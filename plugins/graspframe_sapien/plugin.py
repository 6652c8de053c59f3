"""Registers the SAPIEN backend."""

from graspframe.plugin_system import hookimpl
from graspframe_sapien.backend import SapienBackend


@hookimpl
def graspframe_register_backends(register):
    register(SapienBackend)
