from __future__ import annotations

import pytest

from graspframe.common.errors import UnknownNameError
from graspframe.common.grasps import HumanGrasp


def test_cutkosky_numbers_and_volar_flags():
    numbers = {g.value: g.cutkosky_number for g in HumanGrasp}
    assert numbers == {
        "large_diameter": 1,
        "small_diameter": 2,
        "abducted_thumb": 4,
        "pinch": 9,
        "power_sphere": 10,
        "precision_disc": 12,
    }
    assert {g.value for g in HumanGrasp if g.volar_for_robot} == {
        "large_diameter",
        "small_diameter",
    }
    assert {g.value for g in HumanGrasp if g.volar_for_human} == {
        "large_diameter",
        "small_diameter",
        "abducted_thumb",
        "power_sphere",
    }


def test_parse_is_tolerant_but_never_guesses():
    assert HumanGrasp.parse("Power-Sphere") is HumanGrasp.POWER_SPHERE
    with pytest.raises(UnknownNameError, match="known grasps: abducted_thumb, large_diameter"):
        HumanGrasp.parse("tripod")
