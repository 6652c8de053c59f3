"""`graspframe check-hand NAME`: run the hand contract checks on a registered hand.

Prints, in plain words, either "hand NAME: all checks passed" with a short summary of the
hand, or a numbered list of the problems found: the description checks
(`graspframe.testing.hand_problems`), closing in free space
(`graspframe.testing.grasp_checks.closing_problems`) and, unless asked not to, the hand
alone holding its preshapes' design objects in the registered physics backend
(`hold_problems`). The grasp checks are for robot hands: the human reference hand's
postures are checked by the reference procedure (graspframe/strategy/human_reference.py).
"""

from __future__ import annotations

import typer

from graspframe import registry as registry_module
from graspframe.defaults import DEFAULT_BACKEND
from graspframe.grasps import HUMAN_HAND
from graspframe.hal.descriptions import HandDescription, JointSpec
from graspframe.hal.drivers import Backend
from graspframe.registry import Registry
from graspframe.testing import hand_problems
from graspframe.testing.grasp_checks import closing_problems, hold_problems


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


def check_hand_report(
    hand: HandDescription, backend: Backend | None = None
) -> tuple[bool, list[str]]:
    """(passed, lines to print) for one hand description; with a backend, the hand
    alone must also hold its design objects in it."""
    problems = hand_problems(hand)
    # The grasp checks need a description that loads; the human reference hand's
    # postures are checked by the reference procedure instead.
    if not problems and hand.name != HUMAN_HAND:
        problems += closing_problems(hand)
        if not problems and backend is not None:
            problems += hold_problems(hand, backend)
    if not problems:
        summary = [f"  {line}" for line in hand_summary(hand)]
        return True, [f"hand {hand.name}: all checks passed", *summary]
    count = f"{len(problems)} problem{'s' if len(problems) > 1 else ''}"
    listing = [f"  {i}. {problem}" for i, problem in enumerate(problems, start=1)]
    return False, [f"hand {hand.name}: {count} found", *listing]


def check_hand_command(
    name: str, registry: Registry | None = None, hold: bool = True, backend: str = DEFAULT_BACKEND
) -> int:
    """Check the registered hand `name`; print the result; 0 if it passed, else 1.

    registry: where to look the hand up (default: every installed plugin). An unknown
    name raises the registry's UnknownNameError, which lists the known hands.
    hold: also check that the hand alone holds its design objects, in `backend`.
    """
    registry = registry or registry_module.default_registry()
    hand = registry.get_hand(name)
    physics = registry.get_backend(backend)() if hold else None
    passed, lines = check_hand_report(hand, physics)
    for line in lines:
        typer.echo(line)
    return 0 if passed else 1
