"""JSON files: values made JSON-safe, a JSON input read with a one-line error, a JSON file
written so that a reader never sees half of it."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from graspframe.common.contacts import Contact
from graspframe.common.errors import InputError
from graspframe.common.files import atomic_write


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
    summary = getattr(value, "json_summary", None)
    if callable(summary):  # e.g. a robot model: what it is, not its text
        return jsonable(summary())
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
