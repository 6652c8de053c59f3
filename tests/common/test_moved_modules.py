"""Module paths that moved stay importable for a deprecation period: the old path gives
the module at its new path (the same object) with a DeprecationWarning naming the new
path; the names a package used to export still import from it; the worked plugin example,
written against the old paths, imports unchanged."""

from __future__ import annotations

import ast
import importlib
import importlib.resources
import sys
import warnings
from pathlib import Path

import pytest

from graspframe.common.moved_modules import MOVED

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "docs" / "examples" / "graspframe-parallel-gripper"


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_module_path_gives_the_new_module_with_a_warning(old):
    new = importlib.import_module(MOVED[old])
    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=rf"{old} moved to {MOVED[old]}"):
        module = importlib.import_module(old)
    assert module is new
    assert module.__spec__.name == MOVED[old]  # its own spec, not the old path's


def test_a_moved_package_keeps_its_resources():
    sys.modules.pop("graspframe.demo", None)
    with pytest.warns(DeprecationWarning):
        importlib.import_module("graspframe.demo")
    assert (importlib.resources.files("graspframe.run.demo") / "scene.json").is_file()


@pytest.mark.parametrize(
    ("package", "name", "new"),
    [
        ("graspframe.hal.depth_camera", "Intrinsics", "graspframe.common.camera.Camera"),
        ("graspframe.hal", "Viewer", "graspframe.plugin_system.viewer.Viewer"),
        ("graspframe.hal", "PluginCommand", "graspframe.plugin_system.commands.PluginCommand"),
        ("graspframe.checks", "check_hand_report", "graspframe.checks.hand.check_hand_report"),
        ("graspframe.cli", "app", "graspframe.cli.commands.app"),
        ("graspframe.cli", "main", "graspframe.cli.commands.main"),
    ],
)
def test_a_name_a_package_used_to_export_still_imports(package, name, new):
    module = importlib.import_module(package)
    vars(module).pop(name, None)  # as in a fresh process
    with pytest.warns(DeprecationWarning, match=rf"{package}.{name} moved to {new}"):
        value = getattr(module, name)
    new_module, _, new_name = new.rpartition(".")
    assert value is getattr(importlib.import_module(new_module), new_name)


def test_a_name_no_module_ever_had_is_still_an_attribute_error():
    import graspframe.hal

    with pytest.raises(AttributeError, match="no attribute 'Nothing'"):
        graspframe.hal.Nothing  # noqa: B018


def _graspframe_imports(path: Path) -> list[tuple[str, list[str]]]:
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("graspframe."):
            found.append((node.module, [alias.name for alias in node.names]))
        elif isinstance(node, ast.ImportFrom) and node.module == "graspframe":
            found += [(f"graspframe.{alias.name}", []) for alias in node.names]
    return found


def test_the_worked_plugin_example_imports_unchanged():
    imports = [i for path in EXAMPLE.rglob("*.py") for i in _graspframe_imports(path)]
    assert any(module in MOVED for module, _ in imports)  # it does use old paths
    for module, names in imports:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            imported = importlib.import_module(module)
            for name in names:
                assert hasattr(imported, name), f"from {module} import {name}"


def test_a_descriptions_urdf_method_still_reads_its_model_with_a_warning():
    """A description is data (`model_file()`); its model is read by `model_of`."""
    from graspframe.plugin_system.registry import default_registry
    from graspframe.robot_models.model import model_of

    registry = default_registry()
    for description in (registry.get_hand("barrett"), registry.get_arm("kuka")):
        with pytest.warns(DeprecationWarning, match=r"urdf\(\) is deprecated.*model_of"):
            model = description.urdf()
        assert model is model_of(description)
