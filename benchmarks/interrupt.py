"""Benchmark of how fast Ctrl-C stops each long command.

    python benchmarks/interrupt.py [--repeats 3]

Starts `run`, `evaluate`, `db build` and `check-hand` in a process of their own, sends
SIGINT once each is into its work (the moment the tests interrupt at,
tests/cli/test_interrupts.py), and prints the median wall time [s] from the signal to the
process's exit, with the exit codes seen (130: interrupted). The target is 2 s.
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from startup import GRASPFRAME  # the sibling script in benchmarks/

START_GUARD = 300.0  # [s] for a command to reach the moment it is interrupted


def _children(pid: int) -> list[str]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return path.read_text().split() if path.exists() else []


def _commands(folder: Path) -> dict[str, tuple[list[str], Callable[[int], bool]]]:
    """name -> (arguments, whether the process with this pid is into its work)."""
    runs, sweep, pictures = folder / "runs", folder / "sweep", folder / "pictures"
    return {
        "run": (
            ["run", "--hand", "barrett", "--grasp", "pinch", "--out", str(runs)],
            lambda pid: any(runs.glob("*/result.json")),
        ),
        "evaluate": (
            [
                "evaluate",
                "--hands",
                "barrett",
                "--grasps",
                "pinch,large_diameter",
                "--directions",
                "0",
                "--mount",
                "floating",
                "--workers",
                "2",
                "--out",
                str(sweep),
            ],
            lambda pid: (sweep / "trials.jsonl").exists(),
        ),
        "db build": (
            [
                "db",
                "build",
                "--views-per-grasp",
                "200",
                "--workers",
                "2",
                "--out",
                str(folder / "views.npz"),
            ],
            lambda pid: len(_children(pid)) >= 2,
        ),
        "check-hand": (
            ["check-hand", "barrett", "--pictures", str(pictures)],
            lambda pid: any(pictures.glob("*.png")),
        ),
    }


def stop_wall_s(args: list[str], started: Callable[[int], bool]) -> tuple[float, int]:
    """([s] from SIGINT to the exit, the exit code) of one command."""
    process = subprocess.Popen(
        [*GRASPFRAME, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    since = time.perf_counter()
    while not started(process.pid):
        if process.poll() is not None or time.perf_counter() - since > START_GUARD:
            raise SystemExit(f"{' '.join(args)} ended or hung before it was interrupted")
        time.sleep(0.1)
    time.sleep(1.0)  # into its work
    process.send_signal(signal.SIGINT)
    sent = time.perf_counter()
    code = process.wait()
    return time.perf_counter() - sent, code


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    os.environ.setdefault("GRASPFRAME_CACHE_DIR", tempfile.mkdtemp(prefix="graspframe-cache-"))
    print(f"{'command':<12} {'median [s]':>10}  exit codes")
    for name in ("run", "evaluate", "db build", "check-hand"):
        times, codes = [], []
        for _ in range(args.repeats):
            with tempfile.TemporaryDirectory() as folder:
                command, started = _commands(Path(folder))[name]
                wall_s, code = stop_wall_s(command, started)
            times.append(wall_s)
            codes.append(code)
        print(f"{name:<12} {statistics.median(times):>10.2f}  {sorted(set(codes))}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
