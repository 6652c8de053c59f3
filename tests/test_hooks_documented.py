"""Every hookspec is documented in docs/hooks.md with its exact signature."""

from __future__ import annotations

import inspect
from pathlib import Path

import pytest

from graspframe.plugins import hookspecs

HOOKS_MD = Path(__file__).parents[1] / "docs" / "hooks.md"
HOOKS = [
    (name, fn)
    for name, fn in inspect.getmembers(hookspecs, inspect.isfunction)
    if name.startswith("graspframe_")
]


def test_there_are_hooks():
    assert len(HOOKS) >= 8


@pytest.mark.parametrize(("name", "function"), HOOKS, ids=[n for n, _ in HOOKS])
def test_hook_signature_is_documented(name, function):
    # Annotations are postponed (strings); the documented form shows them unquoted.
    signature = f"{name}{inspect.signature(function)}".replace("'", "")
    text = HOOKS_MD.read_text()
    assert f"`{signature}`" in text, f"docs/hooks.md lacks `{signature}`"
    assert f"## {name}" in text, f"docs/hooks.md lacks a '## {name}' section"
