"""The summary of a sweep: a table per hand and grasp (A beside B) and a bar figure."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from graspframe.common.defaults import STRATEGY_METHOD
from graspframe.common.files import atomic_output, atomic_write
from graspframe.experiments.table_notes import TABLE_NOTE, table_note  # noqa: F401 (re-exported)
from graspframe.experiments.trials import TrialRow, TrialSpec, swept_object

if TYPE_CHECKING:
    from matplotlib.axes import Axes

COLUMNS = (
    "mount",
    "hand",
    "grasp",
    "A_success",
    "A_held_after_lift",
    "A_held_under_disturbance",
    "A_position_err_mm",
    "A_orientation_err_deg",
    "A_robot_vf",
    "A_human_vf",
    "A_robot_epsilon",
    "A_human_epsilon",
    "A_robot_volume",
    "A_human_volume",
    "A_human_held",
    "B_trials",
    "B_successes",
    "B_held_after_lift",
    "B_position_err_mm",
    "B_orientation_err_deg",
    "B_robot_vf_mean",
    "failures",
)


def _mean(values: Iterable[float | None]) -> float | None:
    numbers = [v for v in values if v is not None and math.isfinite(v)]
    return float(np.mean(numbers)) if numbers else None


def size_conditions(rows: list[TrialRow]) -> list[str]:
    """The experiment-A-at-another-size conditions present ("A075", "A125", ...)."""
    conditions = {r.spec.condition for r in rows}
    return sorted(c for c in conditions if c.startswith("A") and c != "A")


OBJECT = "object"  # the column of a sweep over objects, after "grasp"


def mount_label(spec: TrialSpec) -> str:
    """The trial's mount, with its strategy when it is not the method's ("arm/servo")."""
    mount, strategy, noise = spec.mount, spec.strategy, spec.camera_noise
    label = mount if strategy == STRATEGY_METHOD else f"{mount}/{strategy}"
    return label if noise == 1.0 or strategy == STRATEGY_METHOD else f"{label} x{noise:g}"


@dataclass(frozen=True)
class ExperimentA:
    """The numbers of a hand and grasp's experiment-A trial (None: no such trial, or
    not computed), as TrialRow has them; summary.csv's "A_<field>" columns."""

    success: bool | None = None
    held_after_lift: bool | None = None
    held_under_disturbance: bool | None = None
    position_err_mm: float | None = None
    orientation_err_deg: float | None = None
    robot_vf: int | None = None
    human_vf: int | None = None
    robot_epsilon: float | None = None
    human_epsilon: float | None = None
    robot_volume: float | None = None
    human_volume: float | None = None
    human_held: bool | None = None

    @classmethod
    def of(cls, trial: TrialRow | None) -> ExperimentA:
        if trial is None:
            return cls()
        return cls(**{f.name: getattr(trial, f.name) for f in fields(cls)})


@dataclass(frozen=True)
class ExperimentB:
    """Over the B directions of a hand and grasp: how many trials, how many held
    (success) and held after the lift, and the mean errors and robot virtual fingers
    (None: none computed); summary.csv's "B_<field>" columns."""

    trials: int
    successes: int
    held_after_lift: int
    position_err_mm: float | None
    orientation_err_deg: float | None
    robot_vf_mean: float | None

    @classmethod
    def of(cls, trials: list[TrialRow]) -> ExperimentB:
        return cls(
            trials=len(trials),
            successes=sum(bool(t.success) for t in trials),
            held_after_lift=sum(bool(t.held_after_lift) for t in trials),
            position_err_mm=_mean(t.position_err_mm for t in trials),
            orientation_err_deg=_mean(t.orientation_err_deg for t in trials),
            robot_vf_mean=_mean(t.robot_vf for t in trials),
        )


@dataclass(frozen=True)
class SizeHeld:
    """Experiment A on the object at another size (`condition`, e.g. "A075"): held, and
    held after the lift (None: no such trial)."""

    condition: str
    success: bool | None
    held_after_lift: bool | None


@dataclass(frozen=True)
class SummaryRow:
    """One row of the summary: a mount label, hand and grasp (and object, in a sweep
    over objects), experiment A and B, the trials that failed, and A at other sizes."""

    mount: str
    hand: str
    grasp: str
    object: str | None
    a: ExperimentA
    b: ExperimentB
    failures: int
    sizes: tuple[SizeHeld, ...] = ()

    def to_csv(self) -> dict[str, Any]:
        """summary.csv's row: its columns by name (COLUMNS, "object" when set, then
        "<size condition>_success" and "_held_after_lift")."""
        row: dict[str, Any] = {"mount": self.mount, "hand": self.hand, "grasp": self.grasp}
        if self.object is not None:
            row[OBJECT] = self.object
        row.update({f"A_{f.name}": getattr(self.a, f.name) for f in fields(self.a)})
        row.update({f"B_{f.name}": getattr(self.b, f.name) for f in fields(self.b)})
        row["failures"] = self.failures
        for size in self.sizes:
            row[f"{size.condition}_success"] = size.success
            row[f"{size.condition}_held_after_lift"] = size.held_after_lift
        return row


def summarize(rows: list[TrialRow]) -> list[SummaryRow]:
    """One summary row per (mount, hand, grasp), in the order the trials were planned;
    in a sweep over objects, per (mount, hand, grasp, object), with its object.
    Trials of a strategy other than the method's count under their own mount label,
    "<mount>/<strategy>" (e.g. "arm/servo"), so the strategies sit side by side.

    A success: held (after the lift and under the disturbance) in experiment A; the two
    parts are reported separately too. B successes / held_after_lift: counts over the
    B directions. Sizes: experiment A on the object at <size> percent."""
    groups: dict[tuple[str, str, str, str | None], list[TrialRow]] = {}
    for row in rows:
        spec = row.spec
        chosen = swept_object(spec.condition, spec.object)
        key = (mount_label(spec), spec.hand, spec.grasp, chosen)
        groups.setdefault(key, []).append(row)
    sizes = size_conditions(rows)
    summary = []
    for (mount, hand, grasp, chosen), trials in groups.items():
        by_condition = {t.spec.condition: t for t in reversed(trials)}  # the first wins
        sized = []
        for condition in sizes:
            trial = by_condition.get(condition)
            success = None if trial is None else trial.success
            sized.append(
                SizeHeld(condition, success, None if trial is None else trial.held_after_lift)
            )
        summary.append(
            SummaryRow(
                mount=mount,
                hand=hand,
                grasp=grasp,
                object=chosen,
                a=ExperimentA.of(by_condition.get("A")),
                b=ExperimentB.of([t for t in trials if t.spec.condition.startswith("B")]),
                failures=sum(not t.ok or not t.success for t in trials),
                sizes=tuple(sized),
            )
        )
    return summary


def _cell(value: object, decimals: int = 1) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.{decimals}f}"
    return str(value)


def _b_held(b: ExperimentB) -> str:
    """ "n/N (m)": held in n of N B trials, held after the lift in m; "-" without B."""
    if not b.trials:
        return "-"
    return f"{b.successes}/{b.trials} ({b.held_after_lift})"


def _volume(value: float | None) -> str:
    """A wrench-space volume: small numbers of very different sizes, so 2 significant
    digits."""
    return "-" if value is None else f"{value:.2g}"


def _held(success: bool | None, after_lift: bool | None) -> str:
    """ "yes", "no" (not even after the lift) or "lift only" (slipped when pushed)."""
    if success is None:
        return "-"
    if success:
        return "yes"
    return "lift only" if after_lift else "no"


def _size_conditions_of(summary: list[SummaryRow]) -> list[str]:
    """The A-at-another-size conditions ("A075", ...) of the summary (every row has
    them all)."""
    return [size.condition for size in summary[0].sizes] if summary else []


def summary_table(
    summary: list[SummaryRow], experiment: str | None = None
) -> tuple[list[str], list[list[str]]]:
    """The summary as a table for people: (headers, rows of cells as text). Without
    `experiment`, every column, as in summary.md; with "A" or "B", the columns naming
    the row and those of that experiment, headers without its letter (the terminal
    prints one table per experiment: all columns at once are too wide for it)."""
    objects = any(row.object is not None for row in summary)
    sizes = _size_conditions_of(summary)
    names = ["mount", "hand", "grasp", *(["object"] if objects else [])]
    a_headers = [
        "held", "pos err [mm]", "ori err [deg]", "VF robot/human", "epsilon robot/human",
        "volume robot/human", "human held",
    ]  # fmt: skip
    b_headers = ["held (lift)", "pos err [mm]", "ori err [deg]", "VF robot (mean)"]
    size_headers = [f"held at {int(c[1:])}%" for c in sizes]
    if experiment == "A":
        headers = [*names, *a_headers, *size_headers]
    elif experiment == "B":
        headers = [*names, *b_headers, "failures (A and B)"]
    else:
        headers = [
            *names, *(f"A {h}" for h in a_headers), *(f"B {h}" for h in b_headers),
            *(f"A {h}" for h in size_headers), "failures",
        ]  # fmt: skip
    rows = []
    for r in summary:
        a, b = r.a, r.b
        name_cells = [r.mount, r.hand, r.grasp, *([r.object or "-"] if objects else [])]
        a_cells = [
            _held(a.success, a.held_after_lift),
            _cell(a.position_err_mm),
            _cell(a.orientation_err_deg),
            f"{_cell(a.robot_vf)}/{_cell(a.human_vf)}",
            f"{_cell(a.robot_epsilon, 3)}/{_cell(a.human_epsilon, 3)}",
            f"{_volume(a.robot_volume)}/{_volume(a.human_volume)}",
            _cell(a.human_held),
        ]
        b_cells = [
            _b_held(b),
            _cell(b.position_err_mm),
            _cell(b.orientation_err_deg),
            _cell(b.robot_vf_mean),
        ]
        size_cells = [_held(size.success, size.held_after_lift) for size in r.sizes]
        failures = str(r.failures)
        if experiment == "A":
            rows.append([*name_cells, *a_cells, *size_cells])
        elif experiment == "B":
            rows.append([*name_cells, *b_cells, failures])
        else:
            rows.append([*name_cells, *a_cells, *b_cells, *size_cells, failures])
    return headers, rows


def write_tables(
    summary: list[SummaryRow], out_dir: Path, note: str = TABLE_NOTE
) -> tuple[Path, Path]:
    """summary.csv and summary.md (the table, then `note`) in out_dir."""
    csv_path, md_path = Path(out_dir) / "summary.csv", Path(out_dir) / "summary.md"
    objects = any(row.object is not None for row in summary)
    size_columns = [
        f"{c}_{part}"
        for c in _size_conditions_of(summary)
        for part in ("success", "held_after_lift")
    ]
    columns = [*COLUMNS[:3], OBJECT, *COLUMNS[3:]] if objects else list(COLUMNS)
    table = io.StringIO(newline="")
    writer = csv.DictWriter(table, fieldnames=[*columns, *size_columns])
    writer.writeheader()
    for row in summary:
        values = row.to_csv()
        writer.writerow(
            {k: ("" if values.get(k) is None else values[k]) for k in writer.fieldnames}
        )
    atomic_write(csv_path, table.getvalue())
    headers, rows = summary_table(summary)
    lines = [
        f"| {' | '.join(headers)} |",
        "|---" * len(headers) + "|",
        *(f"| {' | '.join(cells)} |" for cells in rows),
        "",
        note,
    ]
    atomic_write(md_path, "\n".join(lines) + "\n")
    return csv_path, md_path


def plot_summary(summary: list[SummaryRow], path: Path) -> Path:
    """Per-grasp bars, both hands: position and orientation error of the virtual fingers
    (A beside B), and the Ferrari-Canny epsilon of experiment A, robot bars beside the
    human reference's (a black tick per grasp: the same object for every hand)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grasps = list(dict.fromkeys(_group(r) for r in summary))
    hands = list(dict.fromkeys((r.mount, r.hand) for r in summary))
    by_key = {(r.mount, r.hand, _group(r)): r for r in summary}
    x = np.arange(len(grasps))
    fig, axes = plt.subplots(3, 1, figsize=(10, 10), sharex=True)
    # One colour per hand and mount in every panel; B hatched, and left out when no B ran.
    colour = {h: f"C{i % 10}" for i, h in enumerate(hands)}
    conditions = ("A", "B") if any(r.b.trials for r in summary) else ("A",)
    series = [(h, c) for h in hands for c in conditions]
    for ax, error, label in (
        (axes[0], _position_err_mm, "position error [mm]"),
        (axes[1], _orientation_err_deg, "orientation error [deg]"),
    ):
        for i, ((mount, hand), condition) in enumerate(series):
            values = [error(by_key.get((mount, hand, g)), condition) for g in grasps]
            _bars(
                ax,
                x,
                i,
                len(series),
                values,
                f"{hand} ({mount}) {condition}",
                colour[mount, hand],
                condition == "B",
            )
        ax.set_ylabel(label)
    axes[0].legend(ncols=min(4, len(series)), fontsize="small")
    ax = axes[2]
    for i, (mount, hand) in enumerate(hands):
        values = [_robot_epsilon(by_key.get((mount, hand, g))) for g in grasps]
        _bars(ax, x, i, len(hands), values, f"{hand} ({mount})", colour[mount, hand], False)
    human = [next((r.a.human_epsilon for r in summary if _group(r) == g), None) for g in grasps]
    ax.hlines(
        [v if v is not None else np.nan for v in human],
        x - 0.45,
        x + 0.45,
        colors="black",
        linewidth=2,
        label="human reference",
    )
    ax.set_ylabel("epsilon (L1), experiment A")
    ax.legend(ncols=min(4, len(hands) + 1), fontsize="small")
    axes[-1].set_xticks(x, grasps, rotation=20)
    for ax in axes:
        ax.grid(axis="y", alpha=0.3)
    fig.suptitle(
        "Robot vs human: virtual-finger errors (A perfect perception, B object error) "
        "and grasp quality"
    )
    fig.tight_layout()
    with atomic_output(path) as stream:
        fig.savefig(stream, format=Path(path).suffix.lstrip(".") or "png", dpi=100)
    plt.close(fig)
    return path


def _group(row: SummaryRow) -> str:
    """A bar group of the figure: the grasp, or in a sweep over objects the object and
    the grasp."""
    return row.grasp if row.object is None else f"{row.object}\n{row.grasp}"


def _position_err_mm(row: SummaryRow | None, condition: str) -> float | None:
    """The figure's bar: experiment A's position error, or B's mean (None: no row)."""
    if row is None:
        return None
    return row.a.position_err_mm if condition == "A" else row.b.position_err_mm


def _orientation_err_deg(row: SummaryRow | None, condition: str) -> float | None:
    if row is None:
        return None
    return row.a.orientation_err_deg if condition == "A" else row.b.orientation_err_deg


def _robot_epsilon(row: SummaryRow | None) -> float | None:
    return None if row is None else row.a.robot_epsilon


def _bars(
    ax: Axes,
    x: NDArray[np.integer],
    index: int,
    count: int,
    values: Sequence[float | None],
    label: str,
    colour: str,
    hatched: bool,
) -> None:
    """One series of bars at slot `index` of `count` per group; a value that was not
    computed is marked "x" rather than drawn as a zero."""
    width = 0.8 / count
    heights = [v if v is not None else 0.0 for v in values]
    bars = ax.bar(
        x + (index - (count - 1) / 2) * width,
        heights,
        width,
        label=label,
        color=colour,
        hatch="//" if hatched else None,
    )
    for bar, value in zip(bars, values, strict=True):
        if value is None:
            ax.annotate("x", (bar.get_x() + bar.get_width() / 2, 0), ha="center")
