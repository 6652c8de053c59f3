"""Benchmark of the servo strategy's cost: one non-volar grasp with the object 5 cm off,
with `--strategy method` and `--strategy servo`, alternating.

    python benchmarks/servo.py [--repeats 3] [--hand barrett] [--grasp pinch]

Each run is a fresh process (`graspframe run ... --object-error-mm 50,0 --no-record`)
after one unmeasured run of each strategy that fills the cache. Prints the median wall
time of each strategy and their difference: what the camera, the self filter, the fits
and the correcting moves add to a trial.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import tempfile
import time

from startup import GRASPFRAME  # the sibling script in benchmarks/

STRATEGIES = ("method", "servo")


def run_wall_s(hand: str, grasp: str, strategy: str) -> float:
    """[s] wall time of one run in its own process."""
    with tempfile.TemporaryDirectory(prefix="graspframe-bench-") as out:
        args = ["run", "--hand", hand, "--grasp", grasp, "--object-error-mm", "50,0"]
        args += ["--strategy", strategy, "--no-record", "--out", out]
        started = time.perf_counter()
        done = subprocess.run([*GRASPFRAME, *args], capture_output=True, text=True)
        wall_s = time.perf_counter() - started
    if done.returncode not in (0, 3):  # 3: ran, not held (the method misses it)
        raise SystemExit(f"graspframe {' '.join(args)} failed:\n{done.stderr[-2000:]}")
    return wall_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--hand", default="barrett")
    parser.add_argument("--grasp", default="pinch")
    args = parser.parse_args()
    os.environ.setdefault("GRASPFRAME_CACHE_DIR", tempfile.mkdtemp(prefix="graspframe-cache-"))
    for strategy in STRATEGIES:
        run_wall_s(args.hand, args.grasp, strategy)  # fills the cache
    times: dict[str, list[float]] = {s: [] for s in STRATEGIES}
    for _ in range(args.repeats):
        for strategy in STRATEGIES:
            times[strategy].append(run_wall_s(args.hand, args.grasp, strategy))
    medians = {s: statistics.median(t) for s, t in times.items()}
    print(f"graspframe run --hand {args.hand} --grasp {args.grasp} --object-error-mm 50,0")
    for strategy, median in medians.items():
        runs = ", ".join(f"{t:.2f}" for t in times[strategy])
        print(f"  --strategy {strategy:<6} median {median:.2f} s  ({runs})")
    print(f"  the servo adds {medians['servo'] - medians['method']:.2f} s to the trial")


if __name__ == "__main__":
    main()
