"""Where the main job's time goes: imports, vision, planning, simulation, pictures,
scoring and the recording.

    python benchmarks/main_job_parts.py [--repeats 3]

Runs `graspframe run --hand karlsruhe` (the bundled demo, recorded) in fresh processes:
one unmeasured run that fills the cache, then `--repeats` measured ones. Each process
times its own stages by wrapping the run's stage functions (graspframe/run/stages.py)
and the observers' calls (the recording), and the parent times the process. Prints the
median of each part [s] and its share of the wall time. "inputs" is reading the
request's names and files; "simulation" is the execution in the world without the
recording's share; "other" is what no part covers in the process (the run folder, the
summary); "start, exit" is Python's start and the process's exit. The parts count the
modules a stage imports when it first needs them (SAPIEN in the simulation, rerun in the
recording) in that stage; one more run under `python -X importtime` sums every import of
the job, wherever it happens (importtime's own bookkeeping included)."""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

# Runs in the measured process: times the stages, then runs the command as a user does.
DRIVER = r"""
import json, sys, time
started = time.perf_counter()
from graspframe.cli.commands import main
from graspframe.plugin_system.registry import Registry, default_registry
default_registry()
import graspframe.run.runner as runner
import graspframe.pictures.snapshots  # the pictures' modules, imported by the runner
parts = {"imports": time.perf_counter() - started}
recording = [0.0]

def timed(name, function):
    def wrapper(*args, **kwargs):
        since, recorded = time.perf_counter(), recording[0]
        try:
            return function(*args, **kwargs)
        finally:
            # The recording's share of this stage is counted as the recording's.
            spent = time.perf_counter() - since - (recording[0] - recorded)
            parts[name] = parts.get(name, 0.0) + spent
    return wrapper

def observed(function):
    def wrapper(*args, **kwargs):
        since = time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            recording[0] += time.perf_counter() - since
    return wrapper

import graspframe.run.request as run_request
run_request.resolve = timed("inputs", run_request.resolve)
runner.write_json = timed("result.json", runner.write_json)
import graspframe.run.stages as run_stages
run_stages.human_grasp = timed("vision", run_stages.human_grasp)
run_stages.plan = timed("planning", run_stages.plan)
run_stages.execute_in_world = timed("simulation", run_stages.execute_in_world)
run_stages.draw_run_snapshots = timed("pictures", run_stages.draw_run_snapshots)
runner.score_grasp = timed("scoring", runner.score_grasp)
for hook in ("notify_run_started", "notify_run_event", "notify_run_finished"):
    setattr(Registry, hook, observed(getattr(Registry, hook)))
code = main(sys.argv[1:])
parts["recording"] = recording[0]
parts["in process"] = time.perf_counter() - started
print("PARTS " + json.dumps(parts), file=sys.stderr)
sys.exit(code)
"""
PARTS = (
    "imports", "inputs", "vision", "planning", "simulation", "pictures", "scoring",
    "recording", "result.json",
)  # fmt: skip


def measured_run() -> tuple[float, dict[str, float]]:
    """(wall time [s] of one main-job process, its parts [s])."""
    with tempfile.TemporaryDirectory(prefix="graspframe-bench-") as out:
        command = [sys.executable, "-c", DRIVER, "run", "--hand", "karlsruhe", "--out", out]
        started = time.perf_counter()
        done = subprocess.run(command, capture_output=True, text=True)
        wall_s = time.perf_counter() - started
    if done.returncode != 0:
        raise SystemExit(f"the main job failed:\n{done.stderr[-2000:]}")
    line = next(line for line in done.stderr.splitlines() if line.startswith("PARTS "))
    return wall_s, json.loads(line.removeprefix("PARTS "))


def import_time_s() -> float:
    """Every module import of one main-job process [s]: the sum of the top-level imports'
    cumulative times that `python -X importtime` reports."""
    with tempfile.TemporaryDirectory(prefix="graspframe-bench-") as out:
        command = [sys.executable, "-X", "importtime", "-m", "graspframe.cli.commands"]
        done = subprocess.run(
            [*command, "run", "--hand", "karlsruhe", "--out", out], capture_output=True, text=True
        )
    if done.returncode != 0:
        raise SystemExit(f"the main job failed:\n{done.stderr[-2000:]}")
    total_us = 0
    for line in done.stderr.splitlines():
        # "import time: self [us] | cumulative | name", nested imports indented
        if line.startswith("import time:") and "cumulative" not in line:
            _, cumulative_us, name = line.removeprefix("import time:").split("|")
            if not name.startswith("  "):
                total_us += int(cumulative_us)
    return total_us / 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    os.environ.setdefault("GRASPFRAME_CACHE_DIR", tempfile.mkdtemp(prefix="graspframe-cache-"))
    measured_run()  # fills the cache (the human reference, the convex pieces)
    runs = [measured_run() for _ in range(args.repeats)]
    wall_s = statistics.median(wall for wall, _ in runs)
    print(f"main job, graspframe run --hand karlsruhe: median {wall_s:.2f} s wall")
    covered = 0.0
    for part in PARTS:
        seconds = statistics.median(parts.get(part, 0.0) for _, parts in runs)
        covered += seconds
        print(f"  {part:<11} {seconds:6.2f} s  {100 * seconds / wall_s:5.1f} %")
    in_process = statistics.median(parts["in process"] for _, parts in runs)
    other = in_process - covered
    outside = wall_s - in_process
    print(f"  {'other':<11} {other:6.2f} s  {100 * other / wall_s:5.1f} %")
    print(f"  {'start, exit':<11} {outside:6.2f} s  {100 * outside / wall_s:5.1f} %")
    imports_s = import_time_s()
    print(f"every import of the job (python -X importtime, one run): {imports_s:.2f} s")


if __name__ == "__main__":
    main()
