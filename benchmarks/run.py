"""Every speed figure of docs/performance.md, one script after the other.

    python benchmarks/run.py [--quick]

Runs benchmarks/startup.py (`graspframe --help`, a mistyped name, the main job end to
end), benchmarks/main_job_parts.py (the main job by part, every import of it),
benchmarks/recording.py (the recording's cost as a ratio), benchmarks/interrupt.py (from
Ctrl-C to the exit of each long command), benchmarks/servo.py (what the servo strategy
adds to a trial), benchmarks/db_build.py (the
view database at the shipped settings, views per second) and benchmarks/sweep.py (the
full A + B sweep with 1 and 2 workers, trials per second and the speed-up), each in a
fresh process, and prints their figures as they come. --quick runs the sweep for one
hand and one direction and builds a tenth of the database. Takes about 10 minutes on 2
cores without --quick.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).parent


def figures(quick: bool) -> list[list[str]]:
    """The benchmark scripts and their arguments, cheapest first."""
    sweep = ["--hands", "barrett", "--directions", "1"] if quick else []
    views = ["--views-per-grasp", "200"] if quick else []
    return [
        ["startup.py", "--repeats", "3"],
        ["main_job_parts.py", "--repeats", "3"],
        ["recording.py", "--repeats", "3"],
        ["interrupt.py", "--repeats", "3" if not quick else "1"],
        ["servo.py", "--repeats", "3" if not quick else "1"],
        ["db_build.py", *views],
        ["sweep.py", "--repeats", "1", *sweep],
    ]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sweep and database")
    args = parser.parse_args()
    for script, *options in figures(args.quick):
        print(f"\n== {script} {' '.join(options)}", flush=True)
        started = time.perf_counter()
        completed = subprocess.run([sys.executable, str(HERE / script), *options])
        if completed.returncode != 0:
            print(f"{script} failed with exit code {completed.returncode}", file=sys.stderr)
            return completed.returncode
        print(f"({script}: {time.perf_counter() - started:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
