"""`graspframe check-hand NAME|SPEC`: the hand and the backend looked up, then the checks
of graspframe/checks/hand.py run on them and their report printed."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from graspframe.common.defaults import DEFAULT_ARM, DEFAULT_BACKEND
from graspframe.common.errors import UnknownNameError
from graspframe.common.grasps import HUMAN_HAND
from graspframe.hal.descriptions import HandDescription
from graspframe.plugin_system import registry as registry_module
from graspframe.plugin_system.registry import Registry

if TYPE_CHECKING:
    from graspframe.checks.grasps import ExperimentObjects


def check_hand_command(
    name: str,
    registry: Registry | None = None,
    hold: bool = True,
    backend: str = DEFAULT_BACKEND,
    pictures: Path | None = None,
    arm: str | None = None,
    held_test: str = "graspframe",
) -> int:
    """Check the hand `name` (registered, or a spec file); print the result; 0 if it
    passed, else 1.

    registry: where to look the hand up (default: every installed plugin). An unknown
    name raises the registry's UnknownNameError, which lists the known hands.
    hold: also check that the hand alone holds its design objects and experiment A's
    object for every human grasp, in `backend`.
    pictures: folder for the pictures of the hold trials (default runs/check-hand/NAME).
    arm: check that the hand's links clear this arm's once mounted (None: no arm).
    held_test: the held test of the hold checks, "graspframe" or "benchmark".
    """
    from graspframe.strategy.held_check import held_test_named

    held = held_test_named(held_test)
    registry = registry or registry_module.default_registry()
    hand = registry.get_hand(name)
    physics = registry.get_backend(backend)() if hold else None
    # The default arm is checked when it is installed; an arm asked for must be.
    asked = arm is not None and (arm != DEFAULT_ARM or DEFAULT_ARM in registry.names("arm"))
    arm_description = registry.get_arm(arm) if asked and arm is not None else None
    experiment = _experiment_objects(registry, hand) if hold else None
    # The checks (contracts, kinematics, pictures) are imported once the names are known:
    # a mistyped name is answered at once.
    from graspframe.checks.hand import check_hand_report

    def progress(message: str) -> None:
        typer.echo(f"· {message}", err=True)

    folder = pictures or Path("runs") / "check-hand" / hand.name
    passed, lines = check_hand_report(
        hand, physics, folder, progress, arm_description, experiment, held
    )
    for line in lines:
        typer.echo(line)
    return 0 if passed else 1


def _experiment_objects(registry: Registry, hand: HandDescription) -> ExperimentObjects | None:
    """Experiment A's object for each grasp of the hand, and the human hand that places
    the palm on it; None for the human hand, or a registry without them (a plugin's own
    test registry)."""
    from graspframe.checks.grasps import ExperimentObjects

    if hand.name == HUMAN_HAND:
        return None
    try:
        objects = {grasp: registry.default_object_for(grasp) for grasp in hand.grasp_map}
        return ExperimentObjects(registry.get_hand(HUMAN_HAND), objects)
    except UnknownNameError:
        return None
