"""The layers of docs/architecture.md: each package of the core imports only its own
floor and the floors below, nothing in it imports the simulator or the recorder, and
nothing in it imports a plugin package, not even by name through importlib: plugins are
found through the registry. No plugin package imports another one either: each owns its
pipeline, and what they share is in the core.

Every import counts: at the top of a module, inside a function, or for type checking
only. The floors are read from the layer picture of docs/architecture.md (lowest first,
each listing its packages `name/` and the top-level modules `name.py`), the parts from
the package's tree: nothing here is a hand-kept list of modules.
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import graspframe

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # tools/ is not installed
from tools.layer_walk import picture_floors

PACKAGE = Path(graspframe.__file__).parent
PLUGINS = PACKAGE.parent / "plugins"
FORBIDDEN = ("sapien", "rerun")  # plugins only
# The built-in plugins are the packages graspframe_<name>; graspframe_robots is not a
# plugin but the model files of robots/, which the core reads.
PLUGIN_PREFIX = "graspframe_"
NOT_PLUGINS = ("graspframe_robots",)


# The floors of the layer picture (tools/layer_walk.py reads it, for the walk too).
FLOORS = {name: set(parts) for name, parts in picture_floors().items()}
RANK = {part: rank for rank, parts in enumerate(FLOORS.values()) for part in parts}


def _part(path: Path) -> str:
    return path.relative_to(PACKAGE).parts[0].removesuffix(".py")


def _module(path: Path) -> list[str]:
    """The dotted module name of a file of the package, as a list of names."""
    names = ["graspframe", *path.relative_to(PACKAGE).with_suffix("").parts]
    return names[:-1] if names[-1] == "__init__" else names


def _imports(path: Path) -> list[str]:
    """Every module name imported anywhere in the file (functions and type checking
    included; relative imports resolved)."""
    names = []
    package = _module(path) if path.name == "__init__.py" else _module(path)[:-1]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            if module == "graspframe" or not node.module:
                names += [_name_in(module, alias.name) for alias in node.names]
            else:
                names.append(module)
    return names


def _name_in(package: str, name: str) -> str:
    """The module `from package import name` reads: the submodule `name` when there is
    one, else the package itself (`name` is one of its attributes)."""
    folder = PACKAGE.parent.joinpath(*package.split("."))
    if (folder / name).is_dir() or (folder / f"{name}.py").is_file():
        return f"{package}.{name}"
    return f"{package}.__init__" if package == "graspframe" else package


def test_every_part_of_the_package_is_on_one_floor():
    parts = {_part(path) for path in PACKAGE.rglob("*.py")}
    assert parts <= set(RANK), f"no floor for {sorted(parts - set(RANK))}"
    assert set(RANK) <= parts, f"on a floor but not in the package: {sorted(set(RANK) - parts)}"
    placed = [part for parts in FLOORS.values() for part in parts]
    assert len(placed) == len(set(placed)), "a part is on two floors"


def test_no_floor_imports_a_floor_above_it():
    upward = []
    for path in PACKAGE.rglob("*.py"):
        part = _part(path)
        for name in _imports(path):
            if name.startswith("graspframe."):
                target = name.split(".")[1]
                if RANK[target] > RANK[part]:
                    upward.append(f"{path.relative_to(PACKAGE)} imports {name}")
    assert not upward, "\n".join(upward)


def test_the_parts_of_the_package_import_one_another_without_a_cycle():
    """Also within a floor: each part (a top-level module or subpackage) can be built on
    those it imports, so a floor could always be split along its imports."""
    imported: dict[str, set[str]] = {part: set() for part in RANK}
    for path in PACKAGE.rglob("*.py"):
        part = _part(path)
        for name in _imports(path):
            if name.startswith("graspframe.") and name.split(".")[1] != part:
                imported[part].add(name.split(".")[1])
    done: list[str] = []
    while len(done) < len(imported):
        ready = [part for part in imported if part not in done and imported[part] <= set(done)]
        assert ready, f"an import cycle among {sorted(set(imported) - set(done))}"
        done += ready


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


def _plugin_packages() -> set[str]:
    return {path.name for path in PLUGINS.iterdir() if (path / "__init__.py").is_file()}


def _module_names_in_strings(path: Path) -> list[str]:
    """Every string in the file that names a module of a plugin package (what
    importlib.import_module would be given)."""
    plugin_packages = _plugin_packages()
    return [
        node.value
        for node in ast.walk(ast.parse(path.read_text()))
        if isinstance(node, ast.Constant)
        and isinstance(node.value, str)
        and re.fullmatch(r"\w+(\.\w+)*", node.value)
        and node.value.split(".")[0] in plugin_packages
    ]


def test_the_core_package_names_no_plugin_module_to_import():
    assert PLUGIN_PREFIX + "hog_knn" in _plugin_packages()  # the test sees the plugins
    found = [
        f"{path.relative_to(PACKAGE)} names {name!r}"
        for path in PACKAGE.rglob("*.py")
        for name in _module_names_in_strings(path)
    ]
    assert not found, "\n".join(found)


def _plugin_imports(path: Path) -> list[str]:
    """The modules a plugin file imports (plugins use absolute imports only) and the
    plugin modules it names in strings."""
    names = _module_names_in_strings(path)
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            assert not node.level, f"{path}: a relative import"
            names.append(node.module or "")
    return names


def test_no_plugin_package_imports_another():
    plugin_packages = _plugin_packages()
    found = [
        f"{path.relative_to(PLUGINS)} imports {name}"
        for package in sorted(plugin_packages)
        for path in (PLUGINS / package).rglob("*.py")
        for name in _plugin_imports(path)
        if name.split(".")[0] in plugin_packages - {package}
    ]
    assert not found, "\n".join(found)


def test_the_top_of_the_package_holds_at_most_three_modules():
    """Every module lives in the package of its floor; at the top only the package's own
    files (`__init__`, `__main__`)."""
    loose = sorted(path.name for path in PACKAGE.glob("*.py"))
    assert len(loose) <= 3, loose


def test_the_product_imports_nothing_from_graspframe_testing():
    """graspframe.testing is for plugin authors' tests: check-hand and the runs use the
    checks package, never the test helpers."""
    found = [
        f"{path.relative_to(PACKAGE)} imports {name}"
        for path in PACKAGE.rglob("*.py")
        if _part(path) != "testing"
        for name in _imports(path)
        if name == "graspframe.testing" or name.startswith("graspframe.testing.")
    ]
    assert not found, "\n".join(found)


def test_the_hal_imports_no_cli_library():
    """The HAL holds robot and world interfaces only: the command line's typer (and
    click, under it) stay in the plugin system and the CLI."""
    found = [
        f"{path.relative_to(PACKAGE)} imports {name}"
        for path in (PACKAGE / "hal").rglob("*.py")
        for name in _imports(path)
        if name.split(".")[0] in ("typer", "click")
    ]
    assert not found, "\n".join(found)
