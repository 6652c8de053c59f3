"""Writing what the draft and the synthesis found into spec files.

`draft_spec_file(urdf, out)`: `graspframe spec draft` - the drafted spec, its preshapes
synthesised (or the generic wrap with `synthesize=False`), written to `out`.
`synthesize_spec_file(spec)`: `graspframe check-hand SPEC --synthesize` - the spec's
[preshapes.*] tables and [grasp_map] replaced by synthesised ones, every other line
kept. Each reports the time of its steps through `progress`.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from graspframe.common.errors import InputError
from graspframe.common.files import atomic_write
from graspframe.common.grasps import HumanGrasp
from graspframe.hal.drivers import Backend
from graspframe.mapping.roles import roles_of
from graspframe.mapping.synthesis import Synthesis, synthesize
from graspframe.mapping.tables import preshape_tables
from graspframe.specs.draft import HandDraft, draft_hand
from graspframe.specs.draft_text import generic_wrap, spec_text

HEADER = re.compile(r"^\s*\[{1,2}\s*([^\]]+?)\s*\]{1,2}\s*(#.*)?$")


@dataclass
class Written:
    """A spec file written: where, the draft's notes (what it could not decide), the
    synthesis (None: not run) and the seconds of each step."""

    path: Path
    notes: list[str]
    synthesis: Synthesis | None
    steps: dict[str, float] = field(default_factory=dict)


def draft_spec_file(
    urdf: Path,
    out: Path,
    registry,
    backend: Backend | None,
    progress: Callable[[str], None] = lambda _message: None,
    name: str | None = None,
    workers: int = 1,
) -> Written:
    """Draft the spec of the hand in `urdf` and write it to `out`; with a backend, its
    preshapes synthesised (else the generic wrap), `workers` grasps at once."""
    if not Path(urdf).is_file():
        raise InputError(f"URDF not found: {urdf}")
    if Path(out).suffix.lower() != ".toml":
        raise InputError(f"--out must name a .toml spec file, got {out}")
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    steps: dict[str, float] = {}
    started = time.perf_counter()
    progress(f"drafting from {Path(urdf).name}")
    draft = draft_hand(urdf, name)
    steps["draft"] = time.perf_counter() - started
    draft = _absolute(draft)
    tables, grasp_map = generic_wrap(draft)
    atomic_write(Path(out), spec_text(draft, tables, grasp_map))
    synthesis = None
    if backend is not None:
        started = time.perf_counter()
        hand = registry.get_hand(str(out))
        synthesis = synthesize(hand, registry, backend, progress=progress, workers=workers)
        steps["synthesis"] = time.perf_counter() - started
        atomic_write(
            Path(out), spec_text(draft, preshape_tables(synthesis, draft), synthesis.grasp_map)
        )
    return Written(Path(out), list(draft.notes), synthesis, steps)


def _absolute(draft: HandDraft) -> HandDraft:
    draft.urdf = str(Path(draft.urdf).expanduser().resolve())
    return draft


def synthesize_spec_file(
    spec: Path,
    registry,
    backend: Backend,
    progress: Callable[[str], None] = lambda _message: None,
    grasps: Sequence[HumanGrasp] = tuple(HumanGrasp),
    workers: int = 1,
) -> Written:
    """Replace the spec's preshape tables and grasp map by synthesised ones (for
    `grasps`: every human grasp by default), `workers` grasps at once."""
    started = time.perf_counter()
    hand = registry.get_hand(str(spec))
    draft, _names = roles_of(hand)
    synthesis = synthesize(hand, registry, backend, grasps, progress=progress, workers=workers)
    text = without_tables(Path(spec).read_text(), ("preshapes", "grasp_map"))
    grasp_map = "\n".join(
        ["[grasp_map]", *(f'{g} = "{p}"' for g, p in synthesis.grasp_map.items())]
    )
    tables = preshape_tables(synthesis, draft)
    atomic_write(Path(spec), text.rstrip() + "\n\n" + tables + "\n\n" + grasp_map + "\n")
    return Written(
        Path(spec), list(draft.notes), synthesis, {"synthesis": time.perf_counter() - started}
    )


def without_tables(text: str, roots: tuple[str, ...]) -> str:
    """`text` (TOML) without the tables named `root` or `root.*` for each root, each
    from its header to the next header (their comments and keys)."""
    kept, dropping = [], False
    for line in text.splitlines():
        match = HEADER.match(line)
        if match:
            table = match.group(1)
            dropping = any(table == r or table.startswith(f"{r}.") for r in roots)
        if not dropping:
            kept.append(line)
    return "\n".join(kept) + "\n"
