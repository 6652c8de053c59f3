"""Benchmark the full experiment sweep (A + B) with 1 and 2 workers, side by side.

    python benchmarks/sweep.py [--hands barrett,karlsruhe] [--directions 6] [--repeats 3]

Each repeat runs the sweep once per worker count, in turn, each into a fresh temporary
folder (nothing is resumed). Prints every run's wall time and trials per second, then
per worker count the median over the repeats and its speed-up over the first count.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from graspframe.common.grasps import HumanGrasp
from graspframe.experiments.summary import summarize, write_tables
from graspframe.experiments.sweep import SweepConfig, run_sweep


def sweep_time(hands: tuple[str, ...], directions: int, workers: int) -> tuple[float, int, Path]:
    """(wall time [s], trials, output folder) of one sweep from scratch."""
    out = Path(tempfile.mkdtemp(prefix=f"sweep-{workers}w-"))
    config = SweepConfig(
        hands, tuple(g.value for g in HumanGrasp), out, directions=directions, workers=workers
    )
    started = time.perf_counter()
    rows = run_sweep(config)
    elapsed = time.perf_counter() - started
    write_tables(summarize(rows), out)
    return elapsed, len(rows), out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hands", default="barrett,karlsruhe")
    parser.add_argument("--directions", type=int, default=6)
    parser.add_argument("--workers", default="1,2")
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    hands = tuple(args.hands.split(","))
    counts = [int(w) for w in args.workers.split(",")]
    walls_s: dict[int, list[float]] = {workers: [] for workers in counts}
    trials = 0
    for repeat in range(args.repeats):
        for workers in counts:
            elapsed, trials, out = sweep_time(hands, args.directions, workers)
            walls_s[workers].append(elapsed)
            print(
                f"repeat {repeat + 1}, {workers} worker(s): {trials} trials in {elapsed:.1f} s "
                f"wall, {trials / elapsed:.3f} trials/s  (summary: {out / 'summary.md'})",
                flush=True,
            )
    base_s = statistics.median(walls_s[counts[0]])
    for workers in counts:
        median_s = statistics.median(walls_s[workers])
        print(
            f"median of {args.repeats}, {workers} worker(s): {median_s:.1f} s wall, "
            f"{trials / median_s:.3f} trials/s, {base_s / median_s:.2f}x {counts[0]} worker(s)"
        )


if __name__ == "__main__":
    main()
