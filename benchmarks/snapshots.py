"""What drawing snapshots.png costs in the main job.

Run: python benchmarks/snapshots.py [--hand karlsruhe] [--repeats 3]

Runs `graspframe run --hand <hand> --no-record` as a fresh process (after one unmeasured
warm-up run that fills the cache), each into its own temporary folder, with
`draw_snapshots` timed inside the run, and prints the wall time of each run, the time
spent drawing snapshots.png (the renderer's start in the process included) and their
medians. Set GRASPFRAME_CACHE_DIR to keep the cache apart. Prints its figures; asserts
nothing.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time


def _one_run(hand: str, out: str) -> None:
    """In this process: the main job with its snapshots.png timed; prints a JSON line."""
    import graspframe.run.stages as run_stages
    from graspframe.cli.commands import main

    spent_s: list[float] = []
    draw = run_stages.draw_run_snapshots

    def timed(*args, **kwargs):
        started = time.perf_counter()
        try:
            return draw(*args, **kwargs)
        finally:
            spent_s.append(time.perf_counter() - started)

    run_stages.draw_run_snapshots = timed
    code = main(["run", "--hand", hand, "--no-record", "--out", out])
    print(json.dumps({"exit": code, "draw_s": sum(spent_s)}))


def run(hand: str) -> tuple[float, float]:
    """(wall time [s] of one run process, time [s] it spent in draw_snapshots)."""
    with tempfile.TemporaryDirectory(prefix="graspframe-bench-") as out:
        args = [sys.executable, __file__, "--one-run", out, "--hand", hand]
        started = time.perf_counter()
        done = subprocess.run(args, capture_output=True, text=True, stdin=subprocess.DEVNULL)
        wall_s = time.perf_counter() - started
    report = json.loads(done.stdout.strip().splitlines()[-1]) if done.stdout.strip() else {}
    if done.returncode != 0 or report.get("exit") != 0:
        raise SystemExit(f"{' '.join(args)} failed:\n{done.stderr}")
    return wall_s, float(report["draw_s"])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hand", default="karlsruhe")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--one-run", metavar="OUT", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one_run:
        _one_run(args.hand, args.one_run)
        return

    run(args.hand)  # warm-up: caches, imports from disk
    walls, draws = zip(*(run(args.hand) for _ in range(args.repeats)), strict=True)
    print(f"graspframe run --hand {args.hand} --no-record, {args.repeats} runs")
    print(f"  wall [s]:            {', '.join(f'{t:.2f}' for t in walls)}")
    print(f"  draw_snapshots [s]:  {', '.join(f'{t:.3f}' for t in draws)}")
    print(f"  median wall [s]:     {statistics.median(walls):.2f}")
    print(f"  median drawing [s]:  {statistics.median(draws):.3f}")


if __name__ == "__main__":
    main()
