"""Every hookspec is documented in docs/hooks.md with its exact signature, and every run
event kind with its payload fields."""

from __future__ import annotations

import inspect
import re
from pathlib import Path

import pytest

from graspframe.plugin_system import events, hookspecs

HOOKS_MD = Path(__file__).parents[2] / "docs" / "hooks.md"
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


def _documented_events() -> dict[str, tuple[list[str], bool]]:
    """kind -> (payload fields, observers only) as listed under '## Run events'."""
    section = HOOKS_MD.read_text().split("\n## Run events\n", 1)[1].split("\n## ", 1)[0]
    documented: dict[str, tuple[list[str], bool]] = {}
    for block in section.split("\n### ")[1:]:
        heading, body = block.split("\n", 1)
        fields = re.findall(r"^\| `(\w+)` \|", body, flags=re.MULTILINE)
        documented[heading.strip("`")] = (fields, "*Observers only.*" in body)
    return documented


def test_run_events_are_documented_exactly_as_declared():
    declared = {k.name: (list(k.field_names), k.observer_only) for k in events.EVENT_KINDS}
    documented = _documented_events()
    assert list(documented) == list(declared), "docs/hooks.md lists other event kinds"
    for kind, (fields, observer_only) in declared.items():
        assert documented[kind] == (fields, observer_only), f"docs/hooks.md: {kind} differs"
