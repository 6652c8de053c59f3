"""Experiment sweeps: conditions, local workers and Dask executors, resuming, failures,
summary."""

from __future__ import annotations

import io
import json
import math
import multiprocessing
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from rich.console import Console

from graspframe.cli.evaluate import print_summary
from graspframe.experiments.summary import (
    COLUMNS,
    plot_summary,
    summarize,
    summary_table,
    write_tables,
)
from graspframe.experiments.sweep import SweepConfig, load_finished, plan_trials, run_sweep
from graspframe.experiments.trials import (
    TrialRow,
    TrialSpec,
    experiment_b_errors,
    failed_row,
    run_trial_isolated,
)
from graspframe.experiments.workers import run_in_workers

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
    from graspframe.common.grasps import HumanGrasp

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
    from graspframe.plugin_system.registry import default_registry

    for name in sized.values():  # every sized object is in the catalogue
        default_registry().get_object(name)


def _reduced(out: Path, executor: str) -> SweepConfig:
    return SweepConfig(("barrett",), GRASPS, out, directions=1, executor=executor)


def _numbers(rows):
    return {r.trial_id: tuple(getattr(r, k) for k in NUMBERS) for r in rows}


@pytest.mark.slow
def test_reduced_sweep_local_and_dask_give_the_same_numbers(tmp_path, cache_env):
    local = run_sweep(_reduced(tmp_path / "local", "local"))
    assert len(local) == 4 and all(r.ok for r in local)
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
        sys.executable, "-m", "graspframe.cli.commands", "evaluate", "--hands", "barrett",
        "--grasps", ",".join(GRASPS), "--directions", "1", "--workers", "1",
        "--out", str(out),
    ]  # fmt: skip
    trials = out / "trials.jsonl"
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (trials.exists() and trials.read_text().strip()):
        time.sleep(0.2)
    workers = _children(process.pid)
    process.kill()
    process.wait()
    _wait_gone(workers)  # the workers of a killed sweep exit by themselves
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
    assert row.status == "failed"
    assert row.error == "timed out after 0 s" or str(row.error).startswith("timed out")
    assert row.trial_id == "arm/barrett/pinch/A"


def test_a_trial_that_raises_is_recorded_as_failed_and_the_sweep_goes_on(tmp_path, cache_env):
    config = SweepConfig(("barrett", "nohand"), ("pinch",), tmp_path, directions=0, workers=1)
    rows = run_sweep(config)
    by_id = {r.trial_id: r for r in rows}
    assert by_id["arm/nohand/pinch/A"].status == "failed"
    assert "unknown hand 'nohand'" in str(by_id["arm/nohand/pinch/A"].error)
    assert by_id["arm/barrett/pinch/A"].ok


def _children(pid: int) -> list[int]:
    """The process ids of the children of process `pid` (Linux)."""
    pids = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        pids += [int(x) for x in (task / "children").read_text().split()]
    return pids


def _running(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"  # a zombie has exited


def _wait_gone(pids: list[int], patience: float = 60.0) -> None:
    deadline = time.monotonic() + patience
    while time.monotonic() < deadline and any(_running(pid) for pid in pids):
        time.sleep(0.1)
    assert not [pid for pid in pids if _running(pid)], "a worker outlived its sweep"


def _kill_worker_once_a_trial_started(runs_dir: Path, killed: list[int]) -> None:
    # A trial has started once its run folder holds result.json (status "running").
    while not list(runs_dir.glob("*/result.json")):
        time.sleep(0.05)
    for worker in multiprocessing.active_children():
        os.kill(worker.pid, signal.SIGKILL)
        killed.append(worker.pid)


def test_a_worker_killed_mid_trial_fails_that_trial_and_the_others_run(tmp_path, cache_env):
    # One worker, in plan order: nohand A and B0 fail at once, barrett A is killed
    # mid-trial, barrett B0 runs on a fresh worker.
    config = SweepConfig(("nohand", "barrett"), ("pinch",), tmp_path, directions=1, workers=1)
    killed: list[int] = []
    killer = threading.Thread(
        target=_kill_worker_once_a_trial_started, args=(tmp_path / "runs", killed)
    )
    killer.start()
    rows = run_sweep(config)
    killer.join()
    by_id = {r.trial_id: r for r in rows}
    assert len(killed) == 1
    assert by_id["arm/barrett/pinch/A"].status == "failed"
    assert by_id["arm/barrett/pinch/A"].error == "the trial process died (exit code -9)"
    assert by_id["arm/barrett/pinch/A"].to_json()["hand"] == "barrett"  # the row of any trial
    assert by_id["arm/barrett/pinch/B0"].ok
    assert "unknown hand" in str(by_id["arm/nohand/pinch/B0"].error)
    assert load_finished(tmp_path / "trials.jsonl").keys() == by_id.keys()
    assert not multiprocessing.active_children()
    assert not any(_running(pid) for pid in killed)


def test_a_trial_over_its_time_limit_fails_and_later_trials_run(tmp_path, cache_env):
    # A barrett pinch takes seconds; the unknown hand fails at once on a fresh worker.
    config = SweepConfig(
        ("barrett", "nohand"), ("pinch",), tmp_path, directions=0, workers=1, time_limit=0.5
    )
    by_id = {r.trial_id: r for r in run_sweep(config)}
    assert by_id["arm/barrett/pinch/A"].status == "failed"
    assert by_id["arm/barrett/pinch/A"].error == "timed out after 0 s"
    assert "unknown hand 'nohand'" in str(by_id["arm/nohand/pinch/A"].error)
    assert not multiprocessing.active_children()


def test_a_sweep_stopped_early_leaves_no_worker(tmp_path):
    specs = [TrialSpec("nohand", "pinch", f"B{k}", (0.0, 0.0), 0, str(tmp_path)) for k in range(4)]
    specs.insert(1, TrialSpec("barrett", "pinch", "A", (0.0, 0.0), 0, str(tmp_path)))
    rows = run_in_workers(specs, workers=2, time_limit=300.0)
    first = next(rows)
    assert first.status == "failed"
    pids = [worker.pid for worker in multiprocessing.active_children()]
    assert pids
    rows.close()  # what an exception (Ctrl-C) in the sweep's loop does
    assert not multiprocessing.active_children()
    assert not any(_running(pid) for pid in pids)


# What differs between two runs of the same trial: its wall time and where it was written.
NOT_RESULTS = ("wall_time", "result_path")


@pytest.mark.slow
def test_one_and_two_workers_give_the_same_rows(tmp_path, cache_env):
    # Nothing may carry over from trial to trial in a worker (PhysX, for one, lists
    # contacts in an order that depends on what the process simulated before): the
    # Karlsruhe trial gives the same row before and after the Barrett one.
    error_m = (0.05, 0.0)
    karlsruhe = TrialSpec("karlsruhe", "power_sphere", "B0", error_m, 0, str(tmp_path))
    barrett = TrialSpec("barrett", "small_diameter", "B0", error_m, 0, str(tmp_path))

    def rows(workers):
        rows = run_in_workers([karlsruhe, barrett, karlsruhe], workers, time_limit=300.0)
        lines = [row.to_json() for row in rows]
        return [{k: v for k, v in line.items() if k not in NOT_RESULTS} for line in lines]

    one = rows(1)  # in the order given
    assert all(row["status"] == "ok" for row in one)
    assert one[0] == one[2]
    assert sorted(rows(2), key=json.dumps) == sorted(one, key=json.dumps)


def _trial_row(hand: str, grasp: str, condition: str, success: bool) -> TrialRow:
    return TrialRow(
        TrialSpec(hand, grasp, condition, (0.0, 0.0), 0, "runs"), "ok", success=success,
        held_after_lift=True, held_under_disturbance=success,
        position_err_mm=12.345, orientation_err_deg=3.21, robot_vf=2, human_vf=3,
        robot_epsilon=0.0123, human_epsilon=0.0345, robot_volume=1.2e-5, human_volume=3e-6,
        human_held=True,
    )  # fmt: skip


def test_the_summary_prints_as_terminal_tables_with_nothing_cut():
    """One table per experiment, in rich's box characters rather than markdown; units in
    the headers kept; on a console narrower than a table, every row still whole."""
    rows = [
        _trial_row(hand, grasp, condition, success=condition != "B1")
        for hand in ("barrett", "karlsruhe")
        for grasp in ("large_diameter", "pinch")
        for condition in ("A", "B0", "B1", "A125")
    ]
    summary = summarize(rows)
    console = Console(record=True, width=80, file=io.StringIO())
    print_summary(summary, console)
    text = console.export_text()
    lines = text.splitlines()

    assert "Experiment A: perfect perception" in text
    assert "Experiment B: object position error" in text
    assert "|---" not in text and "───" in text
    for unit in ("[mm]", "[deg]"):
        assert sum(unit in line for line in lines) == 2, unit  # in table A and in table B
    table_b = next(k for k, line in enumerate(lines) if "Experiment B" in line)
    for experiment, table_lines in (("A", lines[:table_b]), ("B", lines[table_b:])):
        _, table_rows = summary_table(summary, experiment)
        for cells in table_rows:  # on one line, each value whole
            line = next(line for line in table_lines if line.split()[:3] == cells[:3])
            assert line.split() == [word for cell in cells for word in cell.split()]
    assert "held: lifted 5 cm" in text


# A trials.jsonl line as the sweep has always written it: the trial id, the spec's fields,
# the status, the numbers (or the error) and the wall time, in this order.
OK_LINE = (
    '{"trial_id": "arm/barrett/pinch/B0", "hand": "barrett", "grasp": "pinch", '
    '"condition": "B0", "object_error": [0.05, 0.0], "seed": 0, "runs_dir": "runs", '
    '"arm": "kuka", "record": false, "mount": "arm", "object": null, "strategy": "method", '
    '"camera_noise": 1.0, "status": "ok", "result_path": "runs/x/result.json", '
    '"success": false, "held_after_lift": true, "held_under_disturbance": false, '
    '"failure_reason": "slipped", "touching_fingers": ["f1", "f2"], "corrections": 1, '
    '"palm_contact": true, "position_err_mm": 12.5, "orientation_err_deg": 3.25, '
    '"robot_vf": 2, "human_vf": 2, "score_error": null, "robot_epsilon": 0.125, '
    '"human_epsilon": null, "robot_volume": 1.5e-05, "human_volume": null, '
    '"human_held": true, "limit_excess_deg": 0.0, "limit_violations": [], '
    '"wall_time": 4.5}'
)
FAILED_LINE = (
    '{"trial_id": "arm/nohand/pinch/A", "hand": "nohand", "grasp": "pinch", '
    '"condition": "A", "object_error": [0.0, 0.0], "seed": 0, "runs_dir": "runs", '
    '"arm": "kuka", "record": false, "mount": "arm", "object": null, "strategy": "method", '
    '"camera_noise": 1.0, "status": "failed", "error": "InputError: unknown hand", '
    '"wall_time": 0.25}'
)


@pytest.mark.parametrize("line", [OK_LINE, FAILED_LINE])
def test_a_trial_row_reads_back_its_line_byte_for_byte(line):
    row = TrialRow.from_json(json.loads(line))
    assert json.dumps(row.to_json()) == line
    assert TrialRow.from_json(json.loads(json.dumps(row.to_json()))) == row


def test_a_trial_row_has_typed_fields():
    ok, failed = (
        TrialRow.from_json(json.loads(OK_LINE)),
        TrialRow.from_json(json.loads(FAILED_LINE)),
    )
    assert ok.ok and ok.spec.object_error == (0.05, 0.0) and ok.touching_fingers == ("f1", "f2")
    assert ok.trial_id == "arm/barrett/pinch/B0" and ok.position_err_mm == 12.5
    assert not failed.ok and failed.error == "InputError: unknown hand" and failed.success is None
    assert failed == failed_row(failed.spec, "InputError: unknown hand", 0.25)


def test_a_summary_row_is_its_csv_row():
    rows = [
        _trial_row("barrett", "pinch", condition, success=condition != "B1")
        for condition in ("A", "B0", "B1", "A075")
    ]
    (row,) = summarize(rows)
    assert row.a.success and row.a.position_err_mm == 12.345
    assert (row.b.trials, row.b.successes, row.b.held_after_lift) == (2, 1, 2)
    assert [(s.condition, s.success) for s in row.sizes] == [("A075", True)]
    csv_row = row.to_csv()
    assert list(csv_row)[: len(COLUMNS)] == list(COLUMNS)
    assert list(csv_row)[len(COLUMNS) :] == ["A075_success", "A075_held_after_lift"]
    assert csv_row["failures"] == 1 and csv_row["B_robot_vf_mean"] == 2.0
