"""Contract tests parametrised over every registered plugin.

Run them on an installation with `pytest --pyargs graspframe.testing.contract_tests`.
"""

from __future__ import annotations

import pytest

from graspframe.common.defaults import DEFAULT_ARM, DEFAULT_BACKEND
from graspframe.common.grasps import HUMAN_HAND
from graspframe.plugin_system.registry import default_registry
from graspframe.testing import (
    assert_arm_contract,
    assert_backend_contract,
    assert_classifier_contract,
    assert_hand_closes,
    assert_hand_contract,
    assert_hand_free_of_self_collision,
    assert_hand_holds_design_objects,
)


def _names(kind: str) -> list[str]:
    return default_registry().names(kind)


def test_no_plugin_failed_to_load() -> None:
    failures = [f"{p.name} ({p.package}): {p.error}" for p in default_registry().failures]
    assert not failures, "plugins failed to load:\n" + "\n".join(failures)


@pytest.mark.parametrize("hand_name", _names("hand"))
def test_hand_contract(hand_name: str) -> None:
    assert_hand_contract(default_registry().get_hand(hand_name))


@pytest.mark.parametrize("hand_name", _names("hand"))
def test_hand_open_preshapes_are_free_of_self_collision(hand_name: str) -> None:
    assert_hand_free_of_self_collision(default_registry().get_hand(hand_name))


# The grasp checks are for robot hands: the human reference hand's postures are checked
# by the reference procedure.
ROBOT_HANDS = [h for h in _names("hand") if h != HUMAN_HAND]


@pytest.mark.parametrize("hand_name", ROBOT_HANDS)
def test_hand_closes_its_preshapes(hand_name: str) -> None:
    assert_hand_closes(default_registry().get_hand(hand_name))


@pytest.mark.parametrize("hand_name", ROBOT_HANDS)
def test_hand_alone_holds_its_design_objects(hand_name: str) -> None:
    registry = default_registry()
    backend = _first("backend", DEFAULT_BACKEND)
    if backend is None:
        pytest.skip("the hold check needs a registered physics backend")
    assert_hand_holds_design_objects(registry.get_hand(hand_name), registry.get_backend(backend)())


@pytest.mark.parametrize("arm_name", _names("arm"))
def test_arm_contract(arm_name: str) -> None:
    assert_arm_contract(default_registry().get_arm(arm_name))


@pytest.mark.parametrize("classifier_name", _names("classifier"))
def test_classifier_contract(classifier_name: str) -> None:
    assert_classifier_contract(default_registry().get_classifier(classifier_name))


def _first(kind: str, preferred: str) -> str | None:
    names = _names(kind)
    return preferred if preferred in names else (names[0] if names else None)


@pytest.mark.parametrize("backend_name", _names("backend"))
def test_backend_contract(backend_name: str) -> None:
    registry = default_registry()
    hand, arm, obj = _first("hand", "barrett"), _first("arm", DEFAULT_ARM), _first("object", "")
    if hand is None or arm is None or obj is None:
        pytest.skip("a backend is checked with a registered hand, arm and object")
    assert_backend_contract(
        registry.get_backend(backend_name),
        registry.get_hand(hand),
        registry.get_arm(arm),
        registry.get_object(obj),
    )
