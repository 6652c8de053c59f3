"""Run events: what every stage of a run tells its observers."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class RunInfo:
    """Identity of a run: its id, output directory and the parameters it was started with."""

    run_id: str
    out_dir: str
    params: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class RunEvent:
    """One thing that happened during a run.

    kind: dotted event name, e.g. "classify.done", "execute.contact", "execute.correction".
    sim_time: simulation time [s] when it happened (None for events outside simulation).
    data: event payload; arrays are numpy arrays, poses 4x4 `T_a_b` matrices.
    """

    kind: str
    sim_time: float | None = None
    data: dict[str, Any] = field(default_factory=dict)
