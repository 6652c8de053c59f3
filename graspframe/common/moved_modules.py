"""Module paths that moved, kept importable for a deprecation period.

graspframe's modules moved into one package per floor of docs/architecture.md (for
example `graspframe.transforms` is now `graspframe.common.transforms`). The old paths
that plugin code may import still work: importing one gives the module at its new path
(the same module object, so classes and state are shared) and a DeprecationWarning that
names the new path. `install()` (called by `graspframe/__init__.py`) puts the finder on
`sys.meta_path`. The old paths will be removed in a later release.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import pkgutil
import sys
import warnings
from collections.abc import Callable
from types import ModuleType
from typing import Any

# old module path -> its new path
MOVED = {
    "graspframe.errors": "graspframe.common.errors",
    "graspframe.transforms": "graspframe.common.transforms",
    "graspframe.grasps": "graspframe.common.grasps",
    "graspframe.contacts": "graspframe.common.contacts",
    "graspframe.files": "graspframe.common.files",
    "graspframe.cache": "graspframe.common.cache",
    "graspframe.defaults": "graspframe.common.defaults",
    "graspframe.results": "graspframe.common.json_files",
    "graspframe.urdf_elements": "graspframe.model_files.urdf_elements",
    "graspframe.urdf_tree": "graspframe.model_files.urdf_tree",
    "graspframe.urdf_model": "graspframe.model_files.urdf_model",
    "graspframe.convex": "graspframe.model_files.convex",
    "graspframe.mesh_geometry": "graspframe.model_files.mesh_geometry",
    "graspframe.robot_model": "graspframe.robot_models.model",
    "graspframe.mounting": "graspframe.robot_models.mounting",
    "graspframe.floating_base": "graspframe.robot_models.floating_base",
    "graspframe.shapes": "graspframe.robot_models.shapes",
    "graspframe.plugins": "graspframe.plugin_system",
    "graspframe.plugins.hookspecs": "graspframe.plugin_system.hookspecs",
    "graspframe.plugins.kinds": "graspframe.plugin_system.kinds",
    "graspframe.registry": "graspframe.plugin_system.registry",
    "graspframe.hal.commands": "graspframe.plugin_system.commands",
    "graspframe.hal.viewer": "graspframe.plugin_system.viewer",
    "graspframe.events": "graspframe.plugin_system.events",
    "graspframe.render": "graspframe.pictures.rasteriser",
    "graspframe.snapshots": "graspframe.pictures.snapshots",
    "graspframe.strategy.held_test": "graspframe.strategy.held_check",
    "graspframe.testing.grasp_checks": "graspframe.checks.grasps",
    "graspframe.testing.self_collision": "graspframe.checks.self_collision",
    "graspframe.testing.contracts": "graspframe.checks.contracts",
    "graspframe.run_request": "graspframe.run.request",
    "graspframe.run_result": "graspframe.run.result",
    "graspframe.run_stages": "graspframe.run.stages",
    "graspframe.runner": "graspframe.run.runner",
    "graspframe.scoring": "graspframe.run.scoring",
    "graspframe.scene": "graspframe.run.scene",
    "graspframe.demo": "graspframe.run.demo",
    "graspframe.commands": "graspframe.cli",
    "graspframe.commands.check_hand": "graspframe.cli.check_hand",
    "graspframe.commands.evaluate": "graspframe.cli.evaluate",
    "graspframe.commands.listing": "graspframe.cli.listing",
    "graspframe.commands.plugin_commands": "graspframe.cli.plugin_commands",
    "graspframe.commands.review": "graspframe.cli.review",
    "graspframe.commands.run_summary": "graspframe.cli.run_summary",
    "graspframe.commands.vision": "graspframe.cli.vision",
    "graspframe.interrupts": "graspframe.cli.interrupts",
}


def _warning_stacklevel() -> int:
    """The stack level of the first frame outside this module and the import machinery,
    so that the warning names the line that imported the old path. (`warnings` itself
    does not count the import machinery's frames.)"""
    frame = sys._getframe(1)
    level = 1
    while frame is not None and (
        frame.f_code.co_filename.startswith("<frozen importlib")
        or frame.f_code.co_filename == __file__
        or frame.f_code.co_name == "__getattr__"  # a package forwarding a moved name
    ):
        if not frame.f_code.co_filename.startswith("<frozen importlib"):
            level += 1
        frame = frame.f_back  # type: ignore[assignment]
    return level


def _warn(old: str, new: str) -> None:
    warnings.warn(
        f"{old} moved to {new}: import it from there ({old} will be removed in a later release)",
        DeprecationWarning,
        stacklevel=_warning_stacklevel(),
    )


class _MovedModuleLoader(importlib.abc.Loader):
    """Loads an old path as the module at its new path."""

    def __init__(self, old: str, new: str) -> None:
        self.old, self.new = old, new
        self._spec: importlib.machinery.ModuleSpec | None = None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        _warn(self.old, self.new)
        module = importlib.import_module(self.new)
        self._spec = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        # The import system stamped the old path's spec on the module: give it back its
        # own (package resources and reloads read it).
        module.__spec__ = self._spec


class _MovedModuleFinder(importlib.abc.MetaPathFinder):
    def find_spec(
        self, fullname: str, path: Any = None, target: ModuleType | None = None
    ) -> importlib.machinery.ModuleSpec | None:
        new = MOVED.get(fullname)
        if new is None:
            return None
        return importlib.util.spec_from_loader(fullname, _MovedModuleLoader(fullname, new))


_FINDER = _MovedModuleFinder()


def install() -> None:
    """Make the old module paths importable (once per process)."""
    if _FINDER not in sys.meta_path:
        sys.meta_path.insert(0, _FINDER)


def forward_old_names(package: str, module: str) -> Callable[[str], Any]:
    """A module `__getattr__` for a package that replaced a module of the same name (now
    `module`): a name of the old module is looked up there, with a DeprecationWarning. The
    package's own submodules are left to the import system."""

    def __getattr__(name: str) -> Any:
        here = sys.modules[package]
        submodules = {info.name for info in pkgutil.iter_modules(here.__path__)}
        if not name.startswith("__") and name not in submodules:
            return moved_name(package, name, module)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__


def moved_name(package: str, name: str, module: str, new_name: str | None = None) -> Any:
    """`name`, once importable from `package`, from the module it lives in now (called
    `new_name` there when it was renamed), with a DeprecationWarning; AttributeError when
    that module has no such name either."""
    target = importlib.import_module(module)
    new_name = new_name or name
    if not hasattr(target, new_name):
        raise AttributeError(f"module {package!r} has no attribute {name!r}")
    _warn(f"{package}.{name}", f"{module}.{new_name}")
    value = getattr(target, new_name)
    setattr(sys.modules[package], name, value)  # warned once: the next lookup finds it
    return value
