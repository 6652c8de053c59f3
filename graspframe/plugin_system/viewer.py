"""A recorded run -> shown to the user (`graspframe review`)."""

from __future__ import annotations

from abc import ABC, abstractmethod
from pathlib import Path
from typing import ClassVar


class Viewer(ABC):
    """Opens a run's recording in a viewer: offered by the plugin that writes the
    recording, so the core knows neither its file nor its viewer program.

    Registered as a class and built with no arguments; `name` is its name, `shows` says
    in a few words which files it opens (the error when no viewer finds a recording
    repeats it).
    """

    name: ClassVar[str]
    shows: ClassVar[str] = ""

    @abstractmethod
    def find(self, path: Path) -> Path | None:
        """The recording this viewer opens for `path` (a run folder, or a file in one),
        or None when it finds none there."""

    @abstractmethod
    def show(self, recording: Path) -> int:
        """Open `recording` (as `find` gave it); returns the viewer's exit code once it
        closes. Raises a GraspframeError (one line) when the viewer cannot start: it is
        not installed, or it needs a display and there is none (then the error says how
        else to view the recording: a web viewer, or another machine)."""
