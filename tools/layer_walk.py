"""Walk along the main job and count how often it climbs back up the floors.

    python -m tools.layer_walk [--depth 4] [--hand karlsruhe] [--grasp large_diameter]

Runs one grasp (`resolve`, then `run_grasp`, no recording, no vision) under a profiler
that sees every call into a module of the core package `graspframe` down to `--depth`
calls below the two entry points (plugins' own frames count towards the depth but are
not on a floor). The floors are read from the layer picture of docs/architecture.md.
The walk is the sequence of floors of those calls, in the order they are made, with
repeats in a row merged; a climb is a step of the walk to a higher floor (back up to a
caller's floor, or up through a callback). Prints the number of calls, of floor changes
and of climbs, and the climbs by (from floor, to floor).

`--floors old` reads the modules of each floor from the package layout before the floors
became packages (top-level modules), so one tree can be compared with the other.
"""

from __future__ import annotations

import argparse
import collections
import itertools
import re
import sys
import tempfile
from pathlib import Path
from types import FrameType
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
# The floors of the layout where every floor was a set of top-level modules, lowest first.
OLD_FLOORS = {
    "basic types": (
        "__init__", "errors", "transforms", "grasps", "contacts", "files", "cache", "defaults",
    ),
    "files": (
        "urdf_elements", "urdf_tree", "urdf_model", "convex", "mesh_geometry", "results",
        "scene", "demo",
    ),
    "descriptions and HAL": ("hal", "events"),
    "robot models": ("robot_model", "mounting", "floating_base", "shapes"),
    "registry": ("registry", "plugins", "specs"),
    "motion and metrics": ("motion", "metrics"),
    "pictures": ("render", "pictures", "snapshots"),
    "perception": ("vision", "perception"),
    "strategy": ("strategy",),
    "checks": ("testing", "checks"),
    "runs": ("run_request", "run_result", "scoring", "runner", "run_stages", "experiments"),
    "CLI": ("cli", "commands", "interrupts"),
}  # fmt: skip
PICTURE_NAME_WIDTH = 14


def picture_floors() -> dict[str, tuple[str, ...]]:
    """The floors of docs/architecture.md's layer picture, lowest first."""
    text = (ROOT / "docs" / "architecture.md").read_text().split("## Layers", 1)[1]
    lines = text[text.index("┌") : text.index("└")].splitlines()[1:]
    boxes: list[list[str]] = [[]]
    for line in lines:
        if "├" in line:
            boxes.append([])
        else:
            boxes[-1].append(line.strip().strip("│").removeprefix(" "))
    floors = {}
    for box in reversed(boxes):
        name = " ".join(row[:PICTURE_NAME_WIDTH].strip() for row in box).strip()
        listing = " ".join(row[PICTURE_NAME_WIDTH:] for row in box)
        floors[name] = tuple(re.findall(r"\b(\w+)(?:\.py\b|/)", listing))
    return floors


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--depth", type=int, default=4)
    parser.add_argument("--hand", default="karlsruhe")
    parser.add_argument("--grasp", default="large_diameter")
    parser.add_argument("--floors", choices=("picture", "old"), default="picture")
    parser.add_argument("--steps", action="store_true", help="print every step of the walk")
    args = parser.parse_args()
    floors = OLD_FLOORS if args.floors == "old" else picture_floors()
    rank = {part: i for i, parts in enumerate(floors.values()) for part in parts}
    names = list(floors)

    if args.floors == "old":
        from graspframe.grasps import HumanGrasp  # type: ignore[import-not-found]
        from graspframe.registry import default_registry  # type: ignore[import-not-found]
        from graspframe.run_request import RunRequest, resolve  # type: ignore[import-not-found]
        from graspframe.runner import run_grasp  # type: ignore[import-not-found]
    else:
        from graspframe.common.grasps import HumanGrasp
        from graspframe.plugin_system.registry import default_registry
        from graspframe.run.request import RunRequest, resolve
        from graspframe.run.runner import run_grasp

    registry = default_registry()
    out = tempfile.mkdtemp()
    request = RunRequest(
        hand=args.hand, grasp=HumanGrasp.parse(args.grasp), record=False, out_root=out
    )
    entries = {resolve.__code__, run_grasp.__code__}
    walk: list[int] = []
    steps: list[str] = []  # the function each step of the walk enters
    calls = 0
    depth_of: dict[int, int] = {}

    def profile(frame: FrameType, event: str, _arg: Any) -> None:
        nonlocal calls
        if event == "return":
            depth_of.pop(id(frame), None)  # an id can be reused by a later frame
            return
        if event != "call":
            return
        parent = frame.f_back
        if frame.f_code in entries:
            depth = 0
        elif parent is not None and id(parent) in depth_of:
            depth = depth_of[id(parent)] + 1
        else:
            return
        if depth > args.depth:
            return
        depth_of[id(frame)] = depth
        module = frame.f_globals.get("__name__", "")
        parts = module.split(".")
        if parts[0] != "graspframe":
            return  # a plugin's or a library's frame: counts towards the depth only
        part = parts[1] if len(parts) > 1 else "__init__"
        if part not in rank:
            return
        calls += 1
        if not walk or walk[-1] != rank[part]:
            walk.append(rank[part])
            steps.append(f"{module}.{frame.f_code.co_qualname}")

    sys.setprofile(profile)
    try:
        inputs = resolve(request, registry)
        run_grasp(request, registry, inputs=inputs)
    finally:
        sys.setprofile(None)
    climbs = collections.Counter((names[a], names[b]) for a, b in itertools.pairwise(walk) if b > a)
    if args.steps:
        for floor, step in zip(walk, steps, strict=True):
            print(f"{names[floor]:>20}  {step}")
    print(f"calls into the core within depth {args.depth}: {calls}")
    print(f"floor changes: {len(walk) - 1}; climbs back up: {sum(climbs.values())}")
    for (low, high), n in climbs.most_common():
        print(f"  {n:4d}  {low} -> {high}")


if __name__ == "__main__":
    main()
