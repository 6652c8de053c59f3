"""Benchmark of the command line's start-up and of the main job end to end.

    python benchmarks/startup.py [--repeats 3]

Prints the median wall time of `graspframe --help` (the import cost every command pays),
of `graspframe run --hand barret` (a mistyped name: the plugins are listed and the error
given before anything heavy is imported) and of the main job, `graspframe run --hand
karlsruhe` on the bundled demo with its recording, each in a fresh process. The main
job's first run fills the cache of combined models and human references
(GRASPFRAME_CACHE_DIR, a temporary folder unless set) and is reported apart; the median
is over the warm runs after it.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from recording import run_wall_s  # the sibling script in benchmarks/

# The installed console script beside this Python, as a user runs it.
_SCRIPT = Path(sys.executable).parent / "graspframe"
GRASPFRAME = (
    [str(_SCRIPT)] if _SCRIPT.exists() else [sys.executable, "-m", "graspframe.cli.commands"]
)


def help_wall_s() -> float:
    """Wall time [s] of one `graspframe --help` process."""
    started = time.perf_counter()
    subprocess.run([*GRASPFRAME, "--help"], check=True, capture_output=True)
    return time.perf_counter() - started


def unknown_hand_wall_s() -> float:
    """Wall time [s] of one `graspframe run --hand barret` process, which must fail with
    the one-line "unknown hand" error."""
    started = time.perf_counter()
    done = subprocess.run([*GRASPFRAME, "run", "--hand", "barret"], capture_output=True, text=True)
    wall = time.perf_counter() - started
    if done.returncode == 0 or "unknown hand 'barret'" not in done.stderr:
        raise SystemExit(f"expected the unknown-hand error, got: {done.stderr.strip()}")
    return wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    os.environ.setdefault("GRASPFRAME_CACHE_DIR", tempfile.mkdtemp(prefix="graspframe-cache-"))
    helps = [help_wall_s() for _ in range(args.repeats)]
    print(f"graspframe --help: median {statistics.median(helps):.2f} s over {args.repeats}")
    unknown = [unknown_hand_wall_s() for _ in range(args.repeats)]
    print(
        f"graspframe run --hand barret (unknown hand): median "
        f"{statistics.median(unknown):.2f} s over {args.repeats}"
    )
    first = run_wall_s("karlsruhe", record=True)
    warm = [run_wall_s("karlsruhe", record=True) for _ in range(args.repeats)]
    print(
        f"graspframe run --hand karlsruhe (with recording): first {first:.2f} s, "
        f"then median {statistics.median(warm):.2f} s over {args.repeats}"
    )


if __name__ == "__main__":
    main()
