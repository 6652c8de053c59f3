"""The synthesis's time, per grasp: the kinematic search (candidates closed and scored,
graspframe/mapping/candidates.py) and the held trials (physics), on a hand drafted from
its URDF.

Run: python benchmarks/synthesis.py [URDF ...] [--grasps pinch,power_sphere]
     (default: the built-in Barrett and Karlsruhe URDFs, every grasp)

Prints its figures; asserts nothing. The kinematic search is what a bigger search space
costs; a held trial that fails costs 1 to 2 s.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from graspframe.common.grasps import HumanGrasp
from graspframe.mapping.spec_files import draft_spec_file
from graspframe.mapping.synthesis import synthesize
from graspframe.plugin_system.registry import default_registry

ROBOTS = Path(__file__).resolve().parents[1] / "robots"
DEFAULT_URDFS = [ROBOTS / "barrett" / "barrett.urdf", ROBOTS / "karlsruhe" / "karlsruhe.urdf"]


def synthesis_times(urdf: Path, grasps: list[HumanGrasp]) -> list[dict[str, object]]:
    """One row per grasp: candidates evaluated, the search [s] (up to the first held
    trial), the held trials and their time [s], held or not."""
    registry = default_registry()
    backend = registry.get_backend("sapien")()
    first_trial: dict[str, float] = {}

    def progress(message: str) -> None:
        grasp = message.split(":")[0]
        if "held test 1 " in message and grasp not in first_trial:
            first_trial[grasp] = time.perf_counter()

    with tempfile.TemporaryDirectory() as folder:
        spec = Path(folder) / "hand.toml"
        draft_spec_file(urdf, spec, registry, None)
        hand = registry.get_hand(str(spec))
        synthesis = synthesize(hand, registry, backend, grasps, progress=progress)
    rows = []
    ended = time.perf_counter()
    for result in reversed(synthesis.grasps):  # each grasp's end is the next one's start
        started = ended - result.seconds
        trials_s = ended - first_trial.get(result.grasp.value, ended)
        rows.append(
            {
                "grasp": result.grasp.value,
                "candidates": result.evaluated,
                "search [s]": result.seconds - trials_s,
                "held trials": len(result.trials),
                "trials [s]": trials_s,
                "held": bool(result.held),
            }
        )
        ended = started
    return rows[::-1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("urdfs", nargs="*", type=Path, default=DEFAULT_URDFS)
    parser.add_argument("--grasps", default="all")
    args = parser.parse_args()
    grasps = (
        list(HumanGrasp)
        if args.grasps == "all"
        else [HumanGrasp(name) for name in args.grasps.split(",")]
    )
    for urdf in args.urdfs:
        started = time.perf_counter()
        rows = synthesis_times(urdf, grasps)
        print(f"{urdf.name}: {time.perf_counter() - started:.1f} s in all")
        for row in rows:
            print(
                f"  {row['grasp']:16s} {row['candidates']:4d} candidates, search "
                f"{row['search [s]']:5.1f} s; {row['held trials']:2d} held trials "
                f"{row['trials [s]']:5.1f} s; {'held' if row['held'] else 'NOT held'}"
            )


if __name__ == "__main__":
    main()
