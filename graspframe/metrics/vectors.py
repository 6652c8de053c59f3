"""The checked arrays the metrics compute on: (N,3) vectors, unit normals, force directions.

Each check copies its input, refuses what the metric cannot use (wrong shape, NaN,
non-unit normals, zero forces) with a GraspframeError that names the value, and returns
a read-only float array.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from graspframe.common.errors import GraspframeError

UNIT_NORMAL_TOL = 1e-4
"""A normal is accepted as unit when | |n| - 1 | <= this."""
ZERO_FORCE = 1e-12
"""[N] A net force at or below this magnitude has no direction (D_c is undefined)."""

Vectors = NDArray[np.float64]


def checked_vectors(
    values: ArrayLike | Sequence[ArrayLike], what: str, count: int | None = None
) -> Vectors:
    """A read-only float copy of `values` as (N,3), N >= 1, finite; N == count if given."""
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise GraspframeError(f"{what} must be numbers in an (N,3) array") from None
    if array.ndim != 2 or array.shape[1] != 3 or array.shape[0] == 0:
        raise GraspframeError(f"{what} must have shape (N,3) with N >= 1, got {array.shape}")
    if count is not None and array.shape[0] != count:
        raise GraspframeError(f"{what} must have {count} rows (one per contact), got {len(array)}")
    if not np.all(np.isfinite(array)):
        raise GraspframeError(f"{what} contains NaN or infinite values")
    array.setflags(write=False)
    return array


def checked_unit_vectors(values: ArrayLike, what: str, count: int | None = None) -> Vectors:
    """`checked_vectors` whose rows are unit vectors (within UNIT_NORMAL_TOL)."""
    array = checked_vectors(values, what, count)
    lengths = np.linalg.norm(array, axis=1)
    worst = int(np.argmax(np.abs(lengths - 1.0)))
    if abs(lengths[worst] - 1.0) > UNIT_NORMAL_TOL:
        raise GraspframeError(
            f"{what} must be unit vectors (|n| = 1 +- {UNIT_NORMAL_TOL}); "
            f"row {worst} has length {lengths[worst]:.6g}"
        )
    return array


def force_directions(forces: ArrayLike | Sequence[ArrayLike], what: str = "forces") -> Vectors:
    """Unit directions of (F,3) forces [N]; a zero force has none and is rejected."""
    checked = checked_vectors(forces, what)
    magnitudes = np.linalg.norm(checked, axis=1)
    weakest = int(np.argmin(magnitudes))
    if magnitudes[weakest] <= ZERO_FORCE:
        raise GraspframeError(
            f"{what} row {weakest} is a zero force ({magnitudes[weakest]:.3g} N); "
            f"the force coupling needs forces above {ZERO_FORCE} N"
        )
    return checked / magnitudes[:, None]


def force_direction(f: ArrayLike, what: str) -> Vectors:
    """(3,) unit direction of one force [N]."""
    try:
        row = np.asarray(f, dtype=float).reshape(1, 3)
    except (TypeError, ValueError):
        raise GraspframeError(f"{what} must be a 3-vector force [N]") from None
    return force_directions(row, what)[0]
