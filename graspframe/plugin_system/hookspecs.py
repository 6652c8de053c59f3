"""The graspframe hooks. docs/hooks.md documents each one with its exact signature.

Register hooks receive a `register` callback and call it once per thing they provide;
the registry checks the type and the name of each thing and records which plugin and
package provided it. Observer hooks are called for every run; an observer that raises is
logged and the run goes on (in strict mode the error propagates).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import pluggy

if TYPE_CHECKING:
    from graspframe.plugin_system.events import RunEvent, RunInfo

hookspec = pluggy.HookspecMarker("graspframe")


class Register(Protocol):
    """The callback a register hook receives: call it once per thing provided."""

    def __call__(self, item: Any, /) -> None: ...


@hookspec
def graspframe_register_hands(register: Register) -> None:
    """Register robot (and human) hands: call `register(hand_description)` for each."""


@hookspec
def graspframe_register_arms(register: Register) -> None:
    """Register arms: call `register(arm_description)` for each."""


@hookspec
def graspframe_register_backends(register: Register) -> None:
    """Register backends: call `register(BackendClass)` for each (a `Backend` subclass)."""


@hookspec
def graspframe_register_classifiers(register: Register) -> None:
    """Register classifiers: call `register(ClassifierClass)` for each."""


@hookspec
def graspframe_register_objects(register: Register) -> None:
    """Register graspable objects: call `register(object_description)` for each."""


@hookspec
def graspframe_register_cameras(register: Register) -> None:
    """Register depth cameras: call `register(CameraClass)` for each (a `DepthCamera`
    subclass, graspframe.hal.depth_camera); the servo strategy measures the object
    with one."""


@hookspec
def graspframe_register_viewers(register: Register) -> None:
    """Register viewers of recorded runs: call `register(ViewerClass)` for each (a
    `Viewer` subclass); `graspframe review` asks them."""


@hookspec
def graspframe_register_commands(register: Register) -> None:
    """Register commands of the `graspframe` command line: call
    `register(PluginCommand(name, typer_app))` for each (graspframe.hal.PluginCommand)."""


@hookspec
def graspframe_run_started(run: RunInfo) -> None:
    """A run starts: `run` names it and gives its output directory, its parameters and the
    descriptions of its hand, arm and object."""


@hookspec
def graspframe_run_event(run: RunInfo, event: RunEvent) -> None:
    """Something happened during `run`: `event` has a kind (one of those declared in
    graspframe/plugin_system/events.py), a sim_time and data (that kind's payload fields)."""


@hookspec
def graspframe_run_finished(run: RunInfo, result: Any) -> dict[str, str] | None:
    """`run` ended; `result` is its `graspframe.run.result.RunResult` (status "ok" or
    "failed"). Return the files this observer wrote for the run, by name (e.g.
    {"recording": path}); result.json lists them. A file that cannot be written: raise
    an OutputError naming it and the cause (graspframe.common.files.atomic_write does), which
    fails the run."""
