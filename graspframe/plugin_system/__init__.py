"""Plugin machinery: hook specifications, entry-point loading and the registry.

Plugin authors import `hookimpl` from here:

    from graspframe.plugin_system import hookimpl

    @hookimpl
    def graspframe_register_hands(register):
        register(MY_HAND)
"""

from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeVar

import pluggy

_F = TypeVar("_F", bound=Callable[..., object])
_hookimpl = pluggy.HookimplMarker("graspframe")


def hookimpl(function: _F) -> _F:
    """Mark a function as a graspframe hook implementation (keeps its signature typed)."""
    return _hookimpl(function)


@dataclass(frozen=True)
class NotRegistered:
    """What a register hook found and could not register, and why: give it to
    `register` in place of the thing (e.g. a scan whose mass nobody gave). The registry
    keeps it with the plugin, and `graspframe plugins` and `graspframe objects` show it;
    looking the name up fails with the reason.

    name: the name it would have had; reason: one line saying what is missing and how
    to give it.
    """

    name: str
    reason: str


__all__ = ["NotRegistered", "hookimpl"]
