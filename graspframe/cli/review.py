"""`graspframe review RUN`: show a recorded run with the viewer a plugin offers.

The core knows no recording format and no viewer program: each registered `Viewer`
(graspframe/plugin_system/viewer.py; the rerun plugin's opens recording.rrd) is asked in turn for
a recording at the path, and the first that finds one shows it.
"""

from __future__ import annotations

from pathlib import Path

from graspframe.common.errors import InputError, NotAvailableError
from graspframe.plugin_system.registry import Registry, default_registry


def review_command(run: Path, registry: Registry | None = None) -> int:
    """Open the recording of the run folder (or recording file) `run`; returns the
    viewer's exit code. One-line errors: no plugin offers a viewer; no viewer finds a
    recording there; the viewer cannot start (not installed; no display here, when the
    error says how else to view the recording)."""
    registry = registry or default_registry()
    viewers = [entry.item() for entry in registry.entries("viewer")]
    if not viewers:
        raise NotAvailableError(
            "no plugin can show a run: none of the loaded plugins offers a viewer "
            "(`graspframe plugins` lists what each provides)"
        )
    for viewer in viewers:
        recording = viewer.find(run)
        if recording is not None:
            return viewer.show(recording)
    opens = "; ".join(f"the {viewer.name} viewer opens {viewer.shows}" for viewer in viewers)
    raise InputError(f"no recording at {run}; {opens}")
