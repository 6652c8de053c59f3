"""Typed access to one spec's values, with errors that name the spec and the key."""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from graspframe.common.errors import DescriptionError


class SpecReader:
    """Reads the values of the spec file `path`; every error names the file (as a
    `label`: "spec", "sidecar")."""

    def __init__(self, path: Path, label: str = "spec") -> None:
        self.path = path
        self.label = label

    def fail(self, message: str) -> DescriptionError:
        return DescriptionError(f"{self.label} {self.path.name}: {message}")

    def keys(self, table: Mapping[str, Any], accepted: tuple[str, ...], where: str) -> None:
        for key in table:
            if key not in accepted:
                raise self.fail(f"unknown key {key!r} in {where}; accepted: {', '.join(accepted)}")

    def table(
        self, table: Mapping[str, Any], key: str, where: str, required: bool = False
    ) -> dict[str, Any]:
        value = table.get(key, None)
        if value is None:
            if required:
                raise self.fail(f"{where} needs a [{key}] table")
            return {}
        if not isinstance(value, dict):
            raise self.fail(f"{key!r} in {where} must be a table")
        return value

    def text(
        self, table: Mapping[str, Any], key: str, where: str, default: str | None = None
    ) -> str:
        value = table.get(key, default)
        if not isinstance(value, str) or not value:
            raise self.fail(f"{where} needs {key!r}, a non-empty string")
        return value

    def number(
        self, table: Mapping[str, Any], key: str, where: str, default: float | None = None
    ) -> float:
        value = table.get(key, default)
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            raise self.fail(f"{where}: {key!r} must be a finite number, got {value!r}")
        return float(value)

    def vector(self, value: Any, n: int, what: str) -> tuple[float, ...]:
        if (
            not isinstance(value, list)
            or len(value) != n
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        ):
            raise self.fail(f"{what} must be a list of {n} numbers, got {value!r}")
        return tuple(float(v) for v in value)

    def vector3(self, value: Any, what: str) -> tuple[float, float, float]:
        """A list of 3 numbers (a position, a direction, angles)."""
        x, y, z = self.vector(value, 3, what)
        return x, y, z

    def angle(self, table: Mapping[str, Any], key: str, where: str, default: float = 0.0) -> float:
        """`key` [rad] or `key_deg` [deg]; not both."""
        if key in table and f"{key}_deg" in table:
            raise self.fail(f"{where}: give {key!r} [rad] or {key}_deg [deg], not both")
        if f"{key}_deg" in table:
            return math.radians(self.number(table, f"{key}_deg", where))
        return self.number(table, key, where, default)

    def resolve(self, text: str, what: str) -> Path:
        """A path from the spec: ${ENV} and ~ expanded, relative to the spec's folder."""
        expanded = os.path.expandvars(text)
        unset = re.findall(r"\$\{?(\w+)\}?", expanded)
        if unset:
            raise self.fail(
                f"{what} {text!r} uses the environment variable {unset[0]}, which is not "
                f"set; set it to the folder where you unpacked the vendor's files"
            )
        path = Path(expanded).expanduser()
        return path if path.is_absolute() else (self.path.parent / path).resolve()
