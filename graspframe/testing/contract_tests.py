"""Contract tests parametrised over every registered plugin.

Run them on an installation with `pytest --pyargs graspframe.testing.contract_tests`.
"""

from __future__ import annotations

import pytest

from graspframe.registry import default_registry
from graspframe.testing import (
    assert_arm_contract,
    assert_classifier_contract,
    assert_hand_contract,
)


def _names(kind: str) -> list[str]:
    return default_registry().names(kind)


def test_no_plugin_failed_to_load():
    failures = [f"{p.name} ({p.package}): {p.error}" for p in default_registry().failures]
    assert not failures, "plugins failed to load:\n" + "\n".join(failures)


@pytest.mark.parametrize("hand_name", _names("hand"))
def test_hand_contract(hand_name):
    assert_hand_contract(default_registry().get_hand(hand_name))


@pytest.mark.parametrize("arm_name", _names("arm"))
def test_arm_contract(arm_name):
    assert_arm_contract(default_registry().get_arm(arm_name))


@pytest.mark.parametrize("classifier_name", _names("classifier"))
def test_classifier_contract(classifier_name):
    assert_classifier_contract(default_registry().get_classifier(classifier_name))
