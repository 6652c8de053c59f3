"""Model files (URDF) of the built-in robots, shipped inside the graspframe wheel.

Installed as the package `graspframe_robots`; `model_path("barrett/barrett.urdf")` finds
a file whether graspframe runs from a source checkout or from an installed wheel.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path


def model_path(relative: str) -> Path:
    """Absolute path of a model file under robots/, e.g. "kuka_kr5/kuka_kr5.urdf"."""
    path = Path(str(files(__name__).joinpath(relative)))
    if not path.is_file():
        from graspframe.common.errors import DescriptionError

        raise DescriptionError(f"model file {relative!r} is not in the installed robots/ data")
    return path
