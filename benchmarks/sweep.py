"""Benchmark the full experiment sweep (A + B) with 1 and 2 workers.

    python benchmarks/sweep.py [--hands barrett,karlsruhe] [--directions 6]

Prints wall time and trials per second for each worker count; the trials of each run go
to a fresh temporary folder (nothing is resumed).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from graspframe.experiments.summary import summarize, write_tables
from graspframe.experiments.sweep import SweepConfig, run_sweep
from graspframe.grasps import HumanGrasp


def sweep_time(hands: tuple[str, ...], directions: int, workers: int) -> tuple[float, int, Path]:
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
    args = parser.parse_args()
    hands = tuple(args.hands.split(","))
    for workers in (int(w) for w in args.workers.split(",")):
        elapsed, trials, out = sweep_time(hands, args.directions, workers)
        print(
            f"{workers} worker(s): {trials} trials in {elapsed:.1f} s wall, "
            f"{trials / elapsed:.3f} trials/s  (summary: {out / 'summary.md'})"
        )


if __name__ == "__main__":
    main()
