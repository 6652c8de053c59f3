"""Simulate the human reference grasps and check them: held, and touching where the grasp
taxonomy says a person touches (graspframe_human.taxonomy).

    python -m tools.human_references [GRASP,...|all] [SIZES] [--pictures DIR]

SIZES: comma-separated percentages of the default object (default 100,75,125). Prints a
markdown row per grasp and size; with --pictures, draws each grasp at the hold and after
the lift and pushes to DIR/<grasp>_<size>.png. Exit status 1 when a reference fails.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from graspframe_human.taxonomy import contact_problems

from graspframe.common.defaults import DEFAULT_BACKEND
from graspframe.common.grasps import HumanGrasp
from graspframe.plugin_system.registry import default_registry
from graspframe.strategy.human_reference import simulate_human_grasp


def _object(registry, grasp: HumanGrasp, size: int):
    default = registry.default_object_for(grasp)
    return default if size == 100 else registry.get_object(f"{default.name}_{size:03d}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("grasps", nargs="?", default="all")
    parser.add_argument("sizes", nargs="?", default="100,75,125")
    parser.add_argument("--pictures", type=Path, default=None)
    args = parser.parse_args(argv)
    registry = default_registry()
    human = registry.get_hand("human")
    backend = registry.get_backend(DEFAULT_BACKEND)()
    grasps = (
        list(HumanGrasp)
        if args.grasps == "all"
        else [HumanGrasp.parse(g) for g in args.grasps.split(",")]
    )
    sizes = [int(s) for s in args.sizes.split(",")]
    if args.pictures is not None:
        args.pictures.mkdir(parents=True, exist_ok=True)
    print("| grasp | object | held | touching | off the taxonomy |")
    print("|---|---|---|---|---|")
    failures = 0
    for grasp in grasps:
        for size in sizes:
            obj = _object(registry, grasp, size)
            picture = None if args.pictures is None else args.pictures / f"{grasp}_{size}.png"
            start = time.perf_counter()
            reference = simulate_human_grasp(grasp, obj, human, backend, picture=picture)
            problems = contact_problems(grasp, reference.contacts)
            held = "yes" if reference.held.held else f"**no**: {reference.held.failure}"
            failures += (not reference.held.held) or bool(problems)
            print(
                f"| {grasp} | {obj.name} | {held} | {', '.join(reference.touching_fingers)} "
                f"| {'; '.join(problems) or '-'} |",
                flush=True,
            )
            print(f"  ({time.perf_counter() - start:.1f} s)", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
