"""`graspframe review`: a run's rerun recording in the rerun viewer (it ships with
rerun-sdk, as the `rerun` program)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import ClassVar

from graspframe.common.errors import NotAvailableError
from graspframe.plugin_system.viewer import Viewer
from graspframe_rerun import RECORDING_FILE, RECORDING_SUFFIX

# What the native viewer's window library (winit) looks for on Linux; without any of them
# the viewer stops with a raw "EventLoopError" instead of opening a window.
DISPLAY_VARIABLES = ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET")


def has_display() -> bool:
    """Whether the native viewer can open a window here (outside Linux: assumed so)."""
    if not sys.platform.startswith("linux"):
        return True
    return any(os.environ.get(name) for name in DISPLAY_VARIABLES)


class RerunViewer(Viewer):
    """Opens a run folder's recording.rrd, or any .rrd file, in the rerun viewer."""

    name: ClassVar[str] = "rerun"
    shows: ClassVar[str] = f"a run folder's {RECORDING_FILE}, or an {RECORDING_SUFFIX} file"

    def find(self, path: Path) -> Path | None:
        recording = path / RECORDING_FILE if path.is_dir() else path
        if recording.is_file() and recording.suffix == RECORDING_SUFFIX:
            return recording
        return None

    def show(self, recording: Path) -> int:
        on_path = shutil.which("rerun")
        beside_python = Path(sys.executable).parent / "rerun"
        program = on_path or (str(beside_python) if beside_python.is_file() else None)
        if program is None:
            raise NotAvailableError("the rerun viewer is not installed (it ships with rerun-sdk)")
        if not has_display():
            command = "rerun" if on_path else program
            raise NotAvailableError(
                f"no display for the rerun viewer ({', '.join(DISPLAY_VARIABLES)} unset): "
                f"view the recording in a browser with `{command} --web-viewer {recording}`, "
                f"or copy {recording} to a machine with a display and run "
                f"`rerun {recording.name}` there"
            )
        return subprocess.call([program, str(recording)])
