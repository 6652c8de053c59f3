"""Experiment sweeps: conditions, local and Dask executors, resuming, failures, summary."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from graspframe.experiments.summary import plot_summary, summarize, write_tables
from graspframe.experiments.sweep import SweepConfig, load_finished, plan_trials, run_sweep
from graspframe.experiments.trials import TrialSpec, experiment_b_errors, run_trial_isolated

GRASPS = ("large_diameter", "precision_disc")
NUMBERS = ("success", "position_err_mm", "orientation_err_deg", "robot_vf", "human_vf")


@pytest.fixture(scope="module")
def cache_env(tmp_path_factory):
    """A private cache folder, shared by the trial processes of this module."""
    old = os.environ.get("GRASPFRAME_CACHE_DIR")
    os.environ["GRASPFRAME_CACHE_DIR"] = str(tmp_path_factory.mktemp("cache"))
    yield
    if old is None:
        del os.environ["GRASPFRAME_CACHE_DIR"]
    else:
        os.environ["GRASPFRAME_CACHE_DIR"] = old


def test_experiment_b_directions():
    errors = experiment_b_errors(0.05, 6)
    assert [c for c, _ in errors] == ["B0", "B1", "B2", "B3", "B4", "B5"]
    for k, (_, (dx, dy)) in enumerate(errors):
        assert math.hypot(dx, dy) == pytest.approx(0.05)
        assert math.atan2(dy, dx) % (2 * math.pi) == pytest.approx(k * math.pi / 3, abs=1e-12)


def test_full_sweep_plan_has_2_hands_6_grasps_7_conditions(tmp_path):
    from graspframe.grasps import HumanGrasp

    config = SweepConfig(("barrett", "karlsruhe"), tuple(g.value for g in HumanGrasp), tmp_path)
    specs = plan_trials(config)
    assert len(specs) == 2 * 6 * 7
    assert len({s.trial_id for s in specs}) == len(specs)


def test_both_mounts_and_two_sizes_add_their_trials(tmp_path):
    config = SweepConfig(
        ("barrett",), ("large_diameter",), tmp_path, mounts=("arm", "floating"), sizes=(75, 125)
    )
    specs = plan_trials(config)
    assert len(specs) == 2 * (7 + 2)
    sized = {s.trial_id: s.object for s in specs if s.object}
    assert sized == {
        "arm/barrett/large_diameter/A075": "large_cylinder_075",
        "arm/barrett/large_diameter/A125": "large_cylinder_125",
        "floating/barrett/large_diameter/A075": "large_cylinder_075",
        "floating/barrett/large_diameter/A125": "large_cylinder_125",
    }
    from graspframe.registry import default_registry

    for name in sized.values():  # every sized object is in the catalogue
        default_registry().get_object(name)


def _reduced(out: Path, executor: str) -> SweepConfig:
    return SweepConfig(("barrett",), GRASPS, out, directions=1, executor=executor)


def _numbers(rows):
    return {r["trial_id"]: tuple(r.get(k) for k in NUMBERS) for r in rows}


@pytest.mark.slow
def test_reduced_sweep_local_and_dask_give_the_same_numbers(tmp_path, cache_env):
    local = run_sweep(_reduced(tmp_path / "local", "local"))
    assert len(local) == 4 and all(r["status"] == "ok" for r in local)
    dask = run_sweep(_reduced(tmp_path / "dask", "dask"))
    assert _numbers(dask) == _numbers(local)
    # Sweeps are for numbers: no trial is recorded unless asked for.
    assert not list((tmp_path / "local" / "runs").glob("*/recording.rrd"))

    summary = summarize(local)
    csv_path, md_path = write_tables(summary, tmp_path / "local")
    figure = plot_summary(summary, tmp_path / "local" / "summary.png")
    assert "| barrett | large_diameter |" in md_path.read_text()
    assert csv_path.read_text().count("\n") == 1 + len(GRASPS)
    assert figure.stat().st_size > 10_000


@pytest.mark.slow
def test_a_killed_sweep_resumes_without_losing_or_repeating_a_trial(tmp_path, cache_env):
    out = tmp_path / "sweep"
    command = [
        sys.executable, "-m", "graspframe.cli", "evaluate", "--hands", "barrett",
        "--grasps", ",".join(GRASPS), "--directions", "1", "--workers", "1",
        "--out", str(out),
    ]  # fmt: skip
    trials = out / "trials.jsonl"
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (trials.exists() and trials.read_text().strip()):
        time.sleep(0.2)
    process.kill()
    process.wait()
    first = load_finished(trials)
    assert 1 <= len(first) < 4, "the sweep should have been killed part-way"
    with trials.open("a") as stream:  # a line cut short by the kill
        stream.write('{"trial_id": "arm/barrett/precision_disc/B0", "sta')

    subprocess.run(command, check=True, capture_output=True)
    lines = [json.loads(line) for line in trials.read_text().splitlines() if line.endswith("}")]
    ids = [row["trial_id"] for row in lines]
    assert sorted(ids) == sorted(s.trial_id for s in plan_trials(_reduced(out, "local")))
    assert len(ids) == len(set(ids)), "a trial ran twice"
    for trial_id, row in first.items():  # finished trials were kept as they were
        assert load_finished(trials)[trial_id] == row
    assert (out / "summary.md").exists() and (out / "summary.png").exists()


def test_a_trial_over_its_time_limit_is_recorded_as_failed(tmp_path):
    spec = TrialSpec("barrett", "pinch", "A", (0.0, 0.0), 0, str(tmp_path))
    row = run_trial_isolated(spec, time_limit=0.5)
    assert row["status"] == "failed"
    assert row["error"] == "timed out after 0 s" or row["error"].startswith("timed out")
    assert row["trial_id"] == "arm/barrett/pinch/A"


def test_a_trial_that_raises_is_recorded_as_failed_and_the_sweep_goes_on(tmp_path, cache_env):
    config = SweepConfig(("barrett", "nohand"), ("pinch",), tmp_path, directions=0, workers=1)
    rows = run_sweep(config)
    by_id = {r["trial_id"]: r for r in rows}
    assert by_id["arm/nohand/pinch/A"]["status"] == "failed"
    assert "unknown hand 'nohand'" in by_id["arm/nohand/pinch/A"]["error"]
    assert by_id["arm/barrett/pinch/A"]["status"] == "ok"


def test_summary_puts_a_beside_the_mean_of_b():
    rows = [
        {"hand": "h", "grasp": "g", "condition": "A", "status": "ok", "success": True,
         "position_err_mm": 10.0, "orientation_err_deg": 5.0, "robot_vf": 2, "human_vf": 2},
        {"hand": "h", "grasp": "g", "condition": "B0", "status": "ok", "success": True,
         "position_err_mm": 20.0, "orientation_err_deg": 10.0, "robot_vf": 2},
        {"hand": "h", "grasp": "g", "condition": "B1", "status": "ok", "success": False,
         "position_err_mm": 40.0, "orientation_err_deg": 30.0, "robot_vf": 1},
        {"hand": "h", "grasp": "g", "condition": "B2", "status": "failed", "error": "x"},
    ]  # fmt: skip
    (row,) = summarize(rows)
    assert row["mount"] == "arm"
    assert row["A_position_err_mm"] == 10.0
    assert row["B_position_err_mm"] == pytest.approx(30.0)
    assert row["B_orientation_err_deg"] == pytest.approx(20.0)
    assert (row["B_successes"], row["B_trials"], row["failures"]) == (1, 3, 2)


def test_summary_reports_held_after_lift_and_under_disturbance_apart(tmp_path):
    def trial(condition, success, after_lift):
        return {
            "mount": "floating", "hand": "h", "grasp": "g", "condition": condition,
            "status": "ok", "success": success, "held_after_lift": after_lift,
            "held_under_disturbance": success if after_lift else None,
        }  # fmt: skip

    rows = [trial("A", False, True), trial("B0", True, True), trial("B1", False, True)]
    rows += [trial("B2", False, False), trial("A075", True, True), trial("A125", False, False)]
    (row,) = summarize(rows)
    assert (row["A_success"], row["A_held_after_lift"]) == (False, True)
    assert (row["B_successes"], row["B_held_after_lift"], row["B_trials"]) == (1, 2, 3)
    assert (row["A075_success"], row["A125_success"]) == (True, False)
    _, md_path = write_tables([row], tmp_path)
    line = next(x for x in md_path.read_text().splitlines() if x.startswith("| floating"))
    assert line.startswith("| floating | h | g | lift only |")
    assert "| 1/3 (2) |" in line and line.endswith("| yes | no | 4 |")
