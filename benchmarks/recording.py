"""What the rerun recording costs: the main job with and without it.

Run: python benchmarks/recording.py [--hand karlsruhe] [--repeats 3]

Runs `graspframe run --hand <hand>` as a fresh process, alternating with and without
`--no-record` (after one unmeasured warm-up run that fills the cache), each into its own
temporary folder, and prints the median wall time of each and their ratio. Set
GRASPFRAME_CACHE_DIR to keep the cache apart. Prints its figures; asserts nothing.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

GRASPFRAME = [sys.executable, "-m", "graspframe.cli.commands"]


def run_wall_s(hand: str, record: bool) -> float:
    """Wall time [s] of one `graspframe run` process (fails loudly if the run fails)."""
    with tempfile.TemporaryDirectory(prefix="graspframe-bench-") as out:
        args = [*GRASPFRAME, "run", "--hand", hand, "--out", str(Path(out))]
        if not record:
            args.append("--no-record")
        started = time.perf_counter()
        done = subprocess.run(args, capture_output=True, text=True, stdin=subprocess.DEVNULL)
        wall_s = time.perf_counter() - started
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(args)} failed:\n{done.stderr}")
    return wall_s


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hand", default="karlsruhe")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)

    run_wall_s(args.hand, record=True)  # warm-up: caches, imports from disk
    recorded_s, unrecorded_s = [], []
    for _ in range(args.repeats):
        recorded_s.append(run_wall_s(args.hand, record=True))
        unrecorded_s.append(run_wall_s(args.hand, record=False))
    recorded = statistics.median(recorded_s)
    unrecorded = statistics.median(unrecorded_s)
    print(f"graspframe run --hand {args.hand}, {args.repeats} repeats each, alternating")
    print(f"  recorded runs [s]:     {', '.join(f'{t:.2f}' for t in recorded_s)}")
    print(f"  --no-record runs [s]:  {', '.join(f'{t:.2f}' for t in unrecorded_s)}")
    print(f"  median recorded [s]:   {recorded:.2f}")
    print(f"  median --no-record [s]: {unrecorded:.2f}")
    print(f"  ratio recorded / --no-record: {recorded / unrecorded:.2f}")


if __name__ == "__main__":
    main()
