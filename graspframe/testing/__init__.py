"""Public contract tests for graspframe plugins.

A plugin author checks a plugin from their own test suite:

    from graspframe.testing import assert_hand_contract
    assert_hand_contract(MY_HAND)

or runs the parametrised contract tests over every installed plugin:

    pytest --pyargs graspframe.testing.contract_tests

`KinematicBackend` builds worlds without a simulator (no physics, deterministic), for
testing code that drives a `World`.
"""

from graspframe.checks.contracts import (
    arm_problems,
    backend_problems,
    classifier_problems,
    estimate_problems,
    hand_problems,
    palm_direction_problems,
)
from graspframe.checks.grasps import closing_problems, hand_alone_grasp, hold_problems
from graspframe.checks.self_collision import self_collision_problems
from graspframe.hal.classifier import Classifier
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.hal.drivers import Backend
from graspframe.hal.objects import ObjectDescription
from graspframe.testing.kinematic_backend import KinematicBackend


def _assert_none(what: str, problems: list[str]) -> None:
    if problems:
        listing = "\n  - ".join(problems)
        raise AssertionError(f"{what} breaks the contract:\n  - {listing}")


def assert_hand_contract(hand: HandDescription) -> None:
    _assert_none(f"hand {hand.name!r}", hand_problems(hand))


def assert_hand_free_of_self_collision(hand: HandDescription) -> None:
    """No two links overlap in any preshape's open posture, except links that meet by
    design (adjacent, or fixed to each other)."""
    _assert_none(f"hand {hand.name!r}", self_collision_problems(hand))


def assert_hand_closes(hand: HandDescription) -> None:
    """Closing each preshape in free space brings its opposing fingers together."""
    _assert_none(f"hand {hand.name!r}", closing_problems(hand))


def assert_hand_holds_design_objects(hand: HandDescription, backend: Backend) -> None:
    """The hand alone (floating base, no arm) holds each preshape's design object in
    `backend` (an instance, e.g. SapienBackend())."""
    _assert_none(f"hand {hand.name!r}", hold_problems(hand, backend))


def assert_arm_contract(arm: ArmDescription) -> None:
    _assert_none(f"arm {arm.name!r}", arm_problems(arm))


def assert_backend_contract(
    backend_cls: type[Backend], hand: HandDescription, arm: ArmDescription, obj: ObjectDescription
) -> None:
    """`hand`, `arm`, `obj`: descriptions to build the test worlds with."""
    _assert_none(f"backend {backend_cls.name!r}", backend_problems(backend_cls, hand, arm, obj))


def assert_classifier_contract(classifier_cls: type[Classifier]) -> None:
    _assert_none(f"classifier {classifier_cls.name!r}", classifier_problems(classifier_cls))


__all__ = [
    "KinematicBackend",
    "arm_problems",
    "assert_arm_contract",
    "assert_backend_contract",
    "assert_classifier_contract",
    "assert_hand_closes",
    "assert_hand_contract",
    "assert_hand_free_of_self_collision",
    "assert_hand_holds_design_objects",
    "backend_problems",
    "classifier_problems",
    "closing_problems",
    "estimate_problems",
    "hand_alone_grasp",
    "hand_problems",
    "hold_problems",
    "palm_direction_problems",
    "self_collision_problems",
]
