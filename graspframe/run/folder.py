"""The run folder: a fresh runs/<UTC timestamp>-<label>/ for every run, and the versions of
the packages a result was computed with."""

from __future__ import annotations

import platform
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from graspframe.common.errors import OutputError
from graspframe.common.files import os_reason

VERSIONED_PACKAGES = ("graspframe", "sapien", "pin", "placo", "ruckig", "rerun-sdk", "numpy")


def versions() -> dict[str, str]:
    """The version of Python and of every package in VERSIONED_PACKAGES ("not installed")."""
    found = {"python": platform.python_version()}
    for package in VERSIONED_PACKAGES:
        try:
            found[package] = version(package)
        except PackageNotFoundError:
            found[package] = "not installed"
    return found


def new_run_dir(out_root: Path | str, label: str) -> Path:
    """A fresh runs/<UTC timestamp>-<label>/ folder (suffixed if it exists); an OutputError
    naming it and the cause when it cannot be created."""
    stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%S")
    base = Path(out_root) / f"{stamp}-{label}"
    path, n = base, 1
    while True:
        try:
            path.mkdir(parents=True)
            return path
        except FileExistsError:
            n += 1
            path = base.with_name(f"{base.name}-{n}")
        except OSError as error:
            raise OutputError(f"cannot create run folder {path}: {os_reason(error)}") from error
