"""Held tables for the docs, from the trials of a sweep.

    python -m tools.held_table runs/evaluate/trials.jsonl [HAND ...]

prints, per hand, one markdown row per grasp and object (the default object and the
75 % and 125 % variants of experiment A) with the outcome on each mount: "yes" (held
after the lift and under the disturbance), "lift only" (held after the lift, slipped
when pushed), or "no" with the failure reason. The sweep that writes the file:

    graspframe evaluate --mount arm,floating --sizes 75,125 --out runs/evaluate

For a sweep over objects (`graspframe evaluate --objects ...`) it prints one table, a
row per object and grasp, a column per hand and mount.
"""

from __future__ import annotations

import sys
from pathlib import Path

from graspframe.common.grasps import HumanGrasp
from graspframe.experiments.sweep import load_finished
from graspframe.experiments.trials import CONDITION_A, TrialRow, swept_object
from graspframe.plugin_system.registry import default_registry


def _outcome(trial: TrialRow) -> str:
    if trial.success:
        return "yes"
    if trial.held_after_lift:
        return "lift only"
    reason = trial.failure_reason or trial.error or "not run"
    return f"**no**: {reason}"


def held_rows(trials: list[TrialRow], hand: str) -> list[str]:
    """Markdown table rows (header included) of the hand's experiment-A trials."""
    registry = default_registry()
    mounts = sorted({t.spec.mount for t in trials})
    by_key = {
        (t.spec.grasp, t.spec.object or "", t.spec.mount): t
        for t in trials
        if t.spec.hand == hand and t.spec.condition.startswith("A")
    }
    rows = [
        "| grasp | object | " + " | ".join(mounts) + " |",
        "|---|---|" + "---|" * len(mounts),
    ]
    for grasp in HumanGrasp:
        default = registry.default_object_for(grasp).name
        for suffix in ("_075", "", "_125"):
            name = default + suffix
            cells = []
            for mount in mounts:
                trial = by_key.get((grasp.value, name if suffix else "", mount))
                cells.append(_outcome(trial) if trial else "-")
            rows.append(f"| {grasp.value} | {name} | " + " | ".join(cells) + " |")
    return rows


def object_rows(trials: list[TrialRow]) -> list[str]:
    """Markdown table rows (header included) of the experiment-A trials of a sweep over
    objects: a row per object and grasp, a column per hand and mount, and the count."""
    chosen = [t.spec for t in trials if t.spec.condition == CONDITION_A]
    row_of = {t.spec: t for t in trials}
    columns = sorted({(s.hand, s.mount) for s in chosen}, key=lambda c: (c[0], c[1]))
    rows = [
        "| object | grasp | " + " | ".join(f"{h} {m}" for h, m in columns) + " |",
        "|---|---|" + "---|" * len(columns),
    ]
    by_key = {(s.object or "", s.grasp, s.hand, s.mount): row_of[s] for s in chosen}
    for name, grasp in sorted({(s.object or "", s.grasp) for s in chosen}):
        cells = [by_key.get((name, grasp, h, m)) for h, m in columns]
        rows.append(
            f"| {name} | {grasp} | " + " | ".join(_outcome(c) if c else "-" for c in cells) + " |"
        )
    held = sum(bool(row_of[s].success) for s in chosen)
    rows += ["", f"held: {held} of {len(chosen)}"]
    return rows


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__)
        return 2
    path = Path(argv[0])
    trials = list(load_finished(path).values())  # a line cut short by a kill is skipped
    if any(swept_object(t.spec.condition, t.spec.object) for t in trials):
        print("\n".join(object_rows(trials)))
        return 0
    hands = argv[1:] or sorted({t.spec.hand for t in trials})
    for hand in hands:
        print(f"{hand}:\n")
        print("\n".join(held_rows(trials, hand)))
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
