"""`graspframe review`: a run's rerun recording in the rerun viewer (it ships with
rerun-sdk, as the `rerun` program)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path
from typing import ClassVar

from graspframe.errors import NotAvailableError
from graspframe.hal.viewer import Viewer
from graspframe_rerun import RECORDING_FILE, RECORDING_SUFFIX


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
        beside_python = Path(sys.executable).parent / "rerun"
        program = shutil.which("rerun") or (str(beside_python) if beside_python.is_file() else None)
        if program is None:
            raise NotAvailableError("the rerun viewer is not installed (it ships with rerun-sdk)")
        return subprocess.call([program, str(recording)])
