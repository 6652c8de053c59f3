"""Plugin machinery: hook specifications, entry-point loading and the registry.

Plugin authors import `hookimpl` from here:

    from graspframe.plugins import hookimpl

    @hookimpl
    def graspframe_register_hands(register):
        register(MY_HAND)
"""

from collections.abc import Callable
from typing import TypeVar

import pluggy

_F = TypeVar("_F", bound=Callable[..., object])
_hookimpl = pluggy.HookimplMarker("graspframe")


def hookimpl(function: _F) -> _F:
    """Mark a function as a graspframe hook implementation (keeps its signature typed)."""
    return _hookimpl(function)


__all__ = ["hookimpl"]
