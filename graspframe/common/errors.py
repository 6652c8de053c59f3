"""One exception root for everything graspframe raises on purpose.

Messages say what was wrong and what is accepted, in one line, so the CLI can print
them as they are.
"""

from __future__ import annotations

from collections.abc import Iterable


class GraspframeError(Exception):
    """Root of every error graspframe raises deliberately."""


class UnknownNameError(GraspframeError, KeyError):
    """A name (hand, arm, grasp, object, ...) that is not known; lists the known ones."""

    def __init__(self, kind: str, name: str, known: Iterable[str], why: str | None = None) -> None:
        self.kind = kind
        self.name = name
        self.known = sorted(known)
        if why is not None:  # it was found, but could not be registered
            super().__init__(f"{kind} {name!r} is not registered: {why}")
            return
        listing = ", ".join(self.known) if self.known else "none are registered"
        kinds = f"{kind[:-1]}ies" if kind.endswith("y") else f"{kind}s"  # strategy: strategies
        super().__init__(f"unknown {kind} {name!r}; known {kinds}: {listing}")

    def __str__(self) -> str:  # KeyError would otherwise quote the whole message
        return self.args[0]


class PluginError(GraspframeError):
    """A plugin failed to load, to validate or to register."""


class DescriptionError(GraspframeError):
    """A hand, arm or object description is inconsistent."""


class InputError(GraspframeError):
    """User input (a file, an option value) that cannot be used."""


class OutputError(GraspframeError):
    """A file or folder graspframe writes cannot be written (no space left, no permission,
    a file where a folder is needed); the message names the path and the cause."""


class MotionError(GraspframeError):
    """The arm cannot do what was asked: a pose out of reach, a line it cannot follow."""


class NotAvailableError(GraspframeError):
    """A feature that cannot run here: an optional part is not installed (an extra, a
    viewer program), or this version of graspframe does not provide it yet."""


class NoContactsError(GraspframeError):
    """There are no (force-bearing) contacts, so there are no virtual fingers to build."""
