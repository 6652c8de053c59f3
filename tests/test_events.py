"""The run event catalogue (graspframe/events.py) and what observers receive."""

from __future__ import annotations

import pytest

from graspframe import events
from graspframe.errors import GraspframeError


def test_every_kind_is_declared_once_with_distinct_fields():
    names = [kind.name for kind in events.EVENT_KINDS]
    assert len(set(names)) == len(names)
    for kind in events.EVENT_KINDS:
        assert "." in kind.name and kind.when and kind.fields, kind.name
        assert len(set(kind.field_names)) == len(kind.field_names), kind.name


def test_a_payload_must_match_its_declaration():
    kind = events.EXECUTE_BACK_OFF
    kind.check({"gap": 0.01, "travel": -0.01})
    with pytest.raises(GraspframeError, match=r"undeclared payload fields \['speed'\]"):
        kind.check({"gap": 0.01, "travel": -0.01, "speed": 0.05})
    with pytest.raises(GraspframeError, match=r"missing \['travel'\]"):
        kind.check({"gap": 0.01})
    events.EXECUTE_DISTURBANCE.check({"skipped": "this probe cannot push"})  # optional fields
