"""Benchmark of the view database build at the shipped settings.

    python benchmarks/db_build.py [--views-per-grasp N] [--workers 1,2]

Builds the database (2000 views per grasp, 128 px, seed 0 by default) once per worker
count into a temporary folder and prints the wall time and views per second of each,
and the speed-up of the last worker count over the first. The shipped database is not
touched.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from graspframe_hog_knn.database import (
    DEFAULT_SEED,
    DEFAULT_SIZE,
    DEFAULT_VIEWS_PER_GRASP,
    build_database,
)
from graspframe_hog_knn.views import GRASPS


def build_rate(views_per_grasp: int, workers: int) -> tuple[float, float]:
    """(wall seconds, views per second) of one build written to a temporary file."""
    started = time.perf_counter()
    database = build_database(views_per_grasp, DEFAULT_SIZE, workers, seed=DEFAULT_SEED)
    with tempfile.TemporaryDirectory() as folder:
        database.save(Path(folder) / "views.npz")
    seconds = time.perf_counter() - started
    return seconds, views_per_grasp * len(GRASPS) / seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--views-per-grasp", type=int, default=DEFAULT_VIEWS_PER_GRASP)
    parser.add_argument("--workers", default="2", help="comma-separated worker counts")
    args = parser.parse_args()
    rates = []
    for workers in (int(w) for w in args.workers.split(",")):
        seconds, rate = build_rate(args.views_per_grasp, workers)
        rates.append(rate)
        print(
            f"db build, {args.views_per_grasp} views/grasp x {len(GRASPS)} at {DEFAULT_SIZE} px, "
            f"{workers} worker(s): {seconds:.1f} s, {rate:.1f} views/s"
        )
    if len(rates) > 1:
        print(f"speed-up of the last worker count over the first: {rates[-1] / rates[0]:.2f}x")


if __name__ == "__main__":
    main()
