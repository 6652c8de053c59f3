"""`graspframe check-hand NAME`: run the hand contract checks on a registered hand.

Prints, in plain words, either "hand NAME: all checks passed" with a short summary of the
hand, or a numbered list of the problems found by `graspframe.testing.hand_problems`.
"""

from __future__ import annotations

import typer

from graspframe import registry as registry_module
from graspframe.hal.descriptions import HandDescription, JointSpec
from graspframe.registry import Registry
from graspframe.testing import hand_problems


def _limits(joint: JointSpec) -> str:
    return f"{joint.name} [{joint.lower:.4g}, {joint.upper:.4g}]"


def hand_summary(hand: HandDescription) -> list[str]:
    """A few lines saying what the hand is: joints, real fingers, preshapes, mapping."""
    mapping = ", ".join(f"{g.value} -> {p}" for g, p in hand.grasp_map.items())
    fingers = ", ".join(f"{f} ({len(links)} links)" for f, links in hand.real_fingers.items())
    return [
        f"model: {hand.model_path}",
        f"joints ({len(hand.joints)}): {', '.join(_limits(j) for j in hand.joints)}",
        f"real fingers ({len(hand.real_fingers)}): {fingers}",
        f"palm frame: {hand.palm_frame}; palm sensor: {hand.palm_sensor_link}",
        f"preshapes ({len(hand.preshapes)}): {', '.join(hand.preshapes)}",
        f"mapping: {mapping}",
    ]


def check_hand_report(hand: HandDescription) -> tuple[bool, list[str]]:
    """(passed, lines to print) for one hand description."""
    problems = hand_problems(hand)
    if not problems:
        summary = [f"  {line}" for line in hand_summary(hand)]
        return True, [f"hand {hand.name}: all checks passed", *summary]
    count = f"{len(problems)} problem{'s' if len(problems) > 1 else ''}"
    listing = [f"  {i}. {problem}" for i, problem in enumerate(problems, start=1)]
    return False, [f"hand {hand.name}: {count} found", *listing]


def check_hand_command(name: str, registry: Registry | None = None) -> int:
    """Check the registered hand `name`; print the result; 0 if it passed, else 1.

    registry: where to look the hand up (default: every installed plugin). An unknown
    name raises the registry's UnknownNameError, which lists the known hands.
    """
    registry = registry or registry_module.default_registry()
    hand = registry.get_hand(name)
    passed, lines = check_hand_report(hand)
    for line in lines:
        typer.echo(line)
    return 0 if passed else 1
