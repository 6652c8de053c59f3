"""The summary of a sweep: a table per hand and grasp (A beside B) and a bar figure."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

COLUMNS = (
    "hand",
    "grasp",
    "A_success",
    "A_position_err_mm",
    "A_orientation_err_deg",
    "A_robot_vf",
    "A_human_vf",
    "B_trials",
    "B_successes",
    "B_position_err_mm",
    "B_orientation_err_deg",
    "B_robot_vf_mean",
    "failures",
)


def _mean(values) -> float | None:
    numbers = [v for v in values if v is not None and math.isfinite(v)]
    return float(np.mean(numbers)) if numbers else None


def summarize(rows: list[dict]) -> list[dict]:
    """One summary row per (hand, grasp), in the order the trials were planned."""
    groups: dict[tuple[str, str], list[dict]] = {}
    for row in rows:
        groups.setdefault((row["hand"], row["grasp"]), []).append(row)
    summary = []
    for (hand, grasp), trials in groups.items():
        a = next((t for t in trials if t["condition"] == "A"), {})
        b = [t for t in trials if t["condition"].startswith("B")]
        failures = [t for t in trials if t.get("status") != "ok" or not t.get("success")]
        summary.append(
            {
                "hand": hand,
                "grasp": grasp,
                "A_success": a.get("success"),
                "A_position_err_mm": a.get("position_err_mm"),
                "A_orientation_err_deg": a.get("orientation_err_deg"),
                "A_robot_vf": a.get("robot_vf"),
                "A_human_vf": a.get("human_vf"),
                "B_trials": len(b),
                "B_successes": sum(bool(t.get("success")) for t in b),
                "B_position_err_mm": _mean(t.get("position_err_mm") for t in b),
                "B_orientation_err_deg": _mean(t.get("orientation_err_deg") for t in b),
                "B_robot_vf_mean": _mean(t.get("robot_vf") for t in b),
                "failures": len(failures),
            }
        )
    return summary


def _cell(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.1f}"
    return str(value)


def write_tables(summary: list[dict], out_dir: Path) -> tuple[Path, Path]:
    """summary.csv and summary.md in out_dir."""
    csv_path, md_path = Path(out_dir) / "summary.csv", Path(out_dir) / "summary.md"
    with csv_path.open("w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=COLUMNS)
        writer.writeheader()
        for row in summary:
            writer.writerow({k: ("" if row[k] is None else row[k]) for k in COLUMNS})
    lines = [
        "| hand | grasp | A held | A pos err [mm] | A ori err [deg] | A VF robot/human "
        "| B held | B pos err [mm] | B ori err [deg] | B VF robot (mean) | failures |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in summary:
        lines.append(
            f"| {r['hand']} | {r['grasp']} | {_cell(r['A_success'])} "
            f"| {_cell(r['A_position_err_mm'])} | {_cell(r['A_orientation_err_deg'])} "
            f"| {_cell(r['A_robot_vf'])}/{_cell(r['A_human_vf'])} "
            f"| {r['B_successes']}/{r['B_trials']} | {_cell(r['B_position_err_mm'])} "
            f"| {_cell(r['B_orientation_err_deg'])} | {_cell(r['B_robot_vf_mean'])} "
            f"| {r['failures']} |"
        )
    md_path.write_text("\n".join(lines) + "\n")
    return csv_path, md_path


def plot_summary(summary: list[dict], path: Path) -> Path:
    """Per-grasp bars of position and orientation error, both hands, A beside B."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grasps = list(dict.fromkeys(r["grasp"] for r in summary))
    hands = list(dict.fromkeys(r["hand"] for r in summary))
    by_key = {(r["hand"], r["grasp"]): r for r in summary}
    series = [(h, c) for h in hands for c in ("A", "B")]
    width = 0.8 / len(series)
    x = np.arange(len(grasps))
    fig, axes = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    for ax, metric, label in (
        (axes[0], "position_err_mm", "position error [mm]"),
        (axes[1], "orientation_err_deg", "orientation error [deg]"),
    ):
        for i, (hand, condition) in enumerate(series):
            values = [by_key.get((hand, g), {}).get(f"{condition}_{metric}") for g in grasps]
            heights = [v if v is not None else 0.0 for v in values]
            bars = ax.bar(
                x + (i - (len(series) - 1) / 2) * width,
                heights,
                width,
                label=f"{hand} {condition}",
                hatch="//" if condition == "B" else None,
            )
            for bar, value in zip(bars, values, strict=True):
                if value is None:  # not scored: mark it rather than draw a zero
                    ax.annotate("x", (bar.get_x() + bar.get_width() / 2, 0), ha="center")
        ax.set_ylabel(label)
        ax.grid(axis="y", alpha=0.3)
    axes[0].legend(ncols=len(series), fontsize="small")
    axes[1].set_xticks(x, grasps, rotation=20)
    fig.suptitle("Virtual-finger errors, robot vs human: A perfect perception, B object error")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
