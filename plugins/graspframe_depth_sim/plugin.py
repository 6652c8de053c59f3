"""Registers the simulated depth camera."""

from __future__ import annotations

from graspframe.plugin_system import hookimpl
from graspframe_depth_sim.camera import SimulatedDepthCamera


@hookimpl
def graspframe_register_cameras(register):
    register(SimulatedDepthCamera)
