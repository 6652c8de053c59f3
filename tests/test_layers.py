"""The layers of docs/architecture.md: each part of the core package imports only its own
layer and the ones below, nothing in it imports the simulator or the recorder, and
nothing in it imports a plugin package: plugins are found through the registry."""

from __future__ import annotations

import ast
from pathlib import Path

import graspframe

PACKAGE = Path(graspframe.__file__).parent
# Layer of each top-level module or subpackage of graspframe, lowest first.
LAYERS = {
    "core": (
        "__init__", "errors", "transforms", "grasps", "contacts", "hal", "mounting",
        "robot_model", "files", "defaults", "shapes", "events", "plugins", "registry",
        "results", "scene", "floating_base", "demo", "convex", "mesh_geometry", "urdf_elements",
        "urdf_model", "specs",
    ),
    "algorithms": (
        "motion", "metrics", "strategy", "vision", "testing", "checks", "render", "pictures",
        "snapshots",
    ),
    "runs": ("run_request", "run_result", "scoring", "runner", "experiments"),
    "cli": ("cli", "commands"),
}  # fmt: skip
RANK = {part: rank for rank, parts in enumerate(LAYERS.values()) for part in parts}
FORBIDDEN = ("sapien", "rerun")  # plugins only
# The built-in plugins are the packages graspframe_<name>; graspframe_robots is not a
# plugin but the model files of robots/, which the core reads.
PLUGIN_PREFIX = "graspframe_"
NOT_PLUGINS = ("graspframe_robots",)


def _part(path: Path) -> str:
    return path.relative_to(PACKAGE).parts[0].removesuffix(".py")


def _imports(path: Path) -> list[str]:
    """Every module name imported anywhere in the file (functions included)."""
    names = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module == "graspframe":
                names += [f"graspframe.{alias.name}" for alias in node.names]
            else:
                names.append(node.module)
    return names


def test_every_part_of_the_package_has_a_layer():
    parts = {_part(path) for path in PACKAGE.rglob("*.py")}
    assert parts - {"__version__"} <= set(RANK), f"no layer for {parts - set(RANK)}"


def test_no_layer_imports_a_layer_above_it():
    upward = []
    for path in PACKAGE.rglob("*.py"):
        part = _part(path)
        for name in _imports(path):
            if name.startswith("graspframe."):
                target = name.split(".")[1]
                if RANK.get(target, 0) > RANK.get(part, 0):
                    upward.append(f"{path.relative_to(PACKAGE)} imports {name}")
    assert not upward, "\n".join(upward)


def test_the_core_package_never_imports_the_simulator_or_the_recorder():
    found = [
        f"{path.relative_to(PACKAGE)} imports {name}"
        for path in PACKAGE.rglob("*.py")
        for name in _imports(path)
        if name.split(".")[0] in FORBIDDEN
    ]
    assert not found, "\n".join(found)


def test_the_core_package_never_imports_a_plugin_package():
    found = [
        f"{path.relative_to(PACKAGE)} imports {name}"
        for path in PACKAGE.rglob("*.py")
        for name in _imports(path)
        if name.split(".")[0].startswith(PLUGIN_PREFIX) and name.split(".")[0] not in NOT_PLUGINS
    ]
    assert not found, "\n".join(found)
