"""The summary of a sweep: a table per hand and grasp (A beside B) and a bar figure."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

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
    "B_trials",
    "B_successes",
    "B_held_after_lift",
    "B_position_err_mm",
    "B_orientation_err_deg",
    "B_robot_vf_mean",
    "failures",
)


def _mean(values) -> float | None:
    numbers = [v for v in values if v is not None and math.isfinite(v)]
    return float(np.mean(numbers)) if numbers else None


def size_conditions(rows: list[dict]) -> list[str]:
    """The experiment-A-at-another-size conditions present ("A075", "A125", ...)."""
    found = {
        r["condition"] for r in rows if r["condition"].startswith("A") and r["condition"] != "A"
    }
    return sorted(found)


def summarize(rows: list[dict]) -> list[dict]:
    """One summary row per (mount, hand, grasp), in the order the trials were planned.

    A_success: held (after the lift and under the disturbance) in experiment A; the two
    parts are reported separately too. B_successes / B_held_after_lift: counts over the
    B directions. A<size>_success: experiment A on the object at <size> percent."""
    groups: dict[tuple[str, str, str], list[dict]] = {}
    for row in rows:
        key = (row.get("mount", "arm"), row["hand"], row["grasp"])
        groups.setdefault(key, []).append(row)
    sizes = size_conditions(rows)
    summary = []
    for (mount, hand, grasp), trials in groups.items():
        a = next((t for t in trials if t["condition"] == "A"), {})
        b = [t for t in trials if t["condition"].startswith("B")]
        failures = [t for t in trials if t.get("status") != "ok" or not t.get("success")]
        entry = {
            "mount": mount,
            "hand": hand,
            "grasp": grasp,
            "A_success": a.get("success"),
            "A_held_after_lift": a.get("held_after_lift"),
            "A_held_under_disturbance": a.get("held_under_disturbance"),
            "A_position_err_mm": a.get("position_err_mm"),
            "A_orientation_err_deg": a.get("orientation_err_deg"),
            "A_robot_vf": a.get("robot_vf"),
            "A_human_vf": a.get("human_vf"),
            "A_robot_epsilon": a.get("robot_epsilon"),
            "A_human_epsilon": a.get("human_epsilon"),
            "B_trials": len(b),
            "B_successes": sum(bool(t.get("success")) for t in b),
            "B_held_after_lift": sum(bool(t.get("held_after_lift")) for t in b),
            "B_position_err_mm": _mean(t.get("position_err_mm") for t in b),
            "B_orientation_err_deg": _mean(t.get("orientation_err_deg") for t in b),
            "B_robot_vf_mean": _mean(t.get("robot_vf") for t in b),
            "failures": len(failures),
        }
        for condition in sizes:
            trial = next((t for t in trials if t["condition"] == condition), {})
            entry[f"{condition}_success"] = trial.get("success")
            entry[f"{condition}_held_after_lift"] = trial.get("held_after_lift")
        summary.append(entry)
    return summary


def _cell(value, decimals: int = 1) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.{decimals}f}"
    return str(value)


def _held(success, after_lift) -> str:
    """ "yes", "no" (not even after the lift) or "lift only" (slipped when pushed)."""
    if success is None:
        return "-"
    if success:
        return "yes"
    return "lift only" if after_lift else "no"


def write_tables(summary: list[dict], out_dir: Path) -> tuple[Path, Path]:
    """summary.csv and summary.md in out_dir."""
    csv_path, md_path = Path(out_dir) / "summary.csv", Path(out_dir) / "summary.md"
    size_columns = [k for k in (summary[0] if summary else {}) if k not in COLUMNS]
    with csv_path.open("w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=[*COLUMNS, *size_columns])
        writer.writeheader()
        for row in summary:
            writer.writerow({k: ("" if row.get(k) is None else row[k]) for k in writer.fieldnames})
    sizes = [k.removesuffix("_success") for k in size_columns if k.endswith("_success")]
    size_headers = "".join(f" | A held at {int(c[1:])}%" for c in sizes)
    lines = [
        "| mount | hand | grasp | A held | A pos err [mm] | A ori err [deg] | A VF robot/human "
        "| A epsilon robot/human "
        "| B held (lift) | B pos err [mm] | B ori err [deg] | B VF robot (mean)"
        f"{size_headers} | failures |",
        "|---" * (13 + len(sizes)) + "|",
    ]
    for r in summary:
        size_cells = "".join(
            f" | {_held(r[f'{c}_success'], r[f'{c}_held_after_lift'])}" for c in sizes
        )
        lines.append(
            f"| {r['mount']} | {r['hand']} | {r['grasp']} "
            f"| {_held(r['A_success'], r['A_held_after_lift'])} "
            f"| {_cell(r['A_position_err_mm'])} | {_cell(r['A_orientation_err_deg'])} "
            f"| {_cell(r['A_robot_vf'])}/{_cell(r['A_human_vf'])} "
            f"| {_cell(r['A_robot_epsilon'], 3)}/{_cell(r['A_human_epsilon'], 3)} "
            f"| {r['B_successes']}/{r['B_trials']} ({r['B_held_after_lift']}) "
            f"| {_cell(r['B_position_err_mm'])} "
            f"| {_cell(r['B_orientation_err_deg'])} | {_cell(r['B_robot_vf_mean'])}"
            f"{size_cells} | {r['failures']} |"
        )
    lines += [
        "",
        "held: lifted 5 cm and kept in the hand while pushed along +-x, +-y, +-z with half "
        "the object's weight; 'lift only': lifted, then slipped when pushed. "
        "B held (lift): held in n of the directions (held after the lift in m).",
    ]
    md_path.write_text("\n".join(lines) + "\n")
    return csv_path, md_path


def plot_summary(summary: list[dict], path: Path) -> Path:
    """Per-grasp bars of position and orientation error, both hands, A beside B."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grasps = list(dict.fromkeys(r["grasp"] for r in summary))
    hands = list(dict.fromkeys((r["mount"], r["hand"]) for r in summary))
    by_key = {(r["mount"], r["hand"], r["grasp"]): r for r in summary}
    series = [(h, c) for h in hands for c in ("A", "B")]
    width = 0.8 / len(series)
    x = np.arange(len(grasps))
    fig, axes = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    for ax, metric, label in (
        (axes[0], "position_err_mm", "position error [mm]"),
        (axes[1], "orientation_err_deg", "orientation error [deg]"),
    ):
        for i, ((mount, hand), condition) in enumerate(series):
            values = [by_key.get((mount, hand, g), {}).get(f"{condition}_{metric}") for g in grasps]
            heights = [v if v is not None else 0.0 for v in values]
            bars = ax.bar(
                x + (i - (len(series) - 1) / 2) * width,
                heights,
                width,
                label=f"{hand} ({mount}) {condition}",
                hatch="//" if condition == "B" else None,
            )
            for bar, value in zip(bars, values, strict=True):
                if value is None:  # not scored: mark it rather than draw a zero
                    ax.annotate("x", (bar.get_x() + bar.get_width() / 2, 0), ha="center")
        ax.set_ylabel(label)
        ax.grid(axis="y", alpha=0.3)
    axes[0].legend(ncols=min(4, len(series)), fontsize="small")
    axes[1].set_xticks(x, grasps, rotation=20)
    fig.suptitle("Virtual-finger errors, robot vs human: A perfect perception, B object error")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
