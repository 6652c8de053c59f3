"""Run artefacts: the run folder, JSON-safe values, versions, writing result.json safely."""

from __future__ import annotations

import dataclasses
import json
import math
import platform
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np

from graspframe.contacts import Contact
from graspframe.errors import InputError, OutputError
from graspframe.files import atomic_write, os_reason
from graspframe.urdf_model import UrdfModel

VERSIONED_PACKAGES = ("graspframe", "sapien", "pin", "placo", "ruckig", "rerun-sdk", "numpy")


def jsonable(value: Any) -> Any:
    """numpy arrays and scalars, enums, paths, contacts and dataclasses (their fields) as
    plain JSON values."""
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
        return jsonable(value.item())
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Contact):
        return value.to_dict()
    if isinstance(value, UrdfModel):  # a robot model: what it is, not its text
        return {"name": value.name, "digest": value.digest, "sources": jsonable(value.sources)}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        # A typed value: its fields by name, in their order.
        return {f.name: jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple | set | frozenset):
        return [jsonable(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "value") and isinstance(value.value, str):  # StrEnum
        return value.value
    return value


def versions() -> dict[str, str]:
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


def read_json_file(path: Path | str, what: str) -> Any:
    """A JSON input file; an InputError naming `what` if it is missing or malformed."""
    path = Path(path)
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        raise InputError(f"{what} not found: {path}") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"{what} {path} is not readable JSON: {exc}") from exc


def write_json(path: Path, data: dict) -> None:
    """Write `data` as JSON atomically: a reader never sees half a file, and a failed
    write (OutputError: the path and the cause) leaves the file as it was."""
    atomic_write(path, json.dumps(jsonable(data), indent=2))
