"""Thin objects under long fingers: when keeping the hand off the table lifts its fingers
off the object, the planner tries the approaches that keep them on it, or refuses the
grasp in one line saying why; check-hand reports every raise. The hand is the Karlsruhe
hand built at test time from its generator with a 130 mm thumb (50 mm as published)."""

from __future__ import annotations

import types
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from graspframe.checks.grasps import HoldTrial, _unplanned
from graspframe.checks.hand import _plan_lines
from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import make_T
from graspframe.plugin_system import hookimpl
from graspframe.plugin_system.registry import Registry
from graspframe.strategy.arm_path import floating_plan
from graspframe.strategy.planner import PlanningError, PlanningTarget, plan_grasp
from graspframe.strategy.reference_poses import reference_placement

LONG_THUMB_MM = 130.0


@pytest.fixture(scope="module")
def registry(tmp_path_factory) -> Registry:
    """Every installed plugin, and the Karlsruhe hand with a 130 mm thumb as `long_thumb`."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # tools/ is not installed
    import tools.robot_models.karlsruhe as generator

    folder = tmp_path_factory.mktemp("long_thumb")
    published = generator.THUMB_DISTAL_MM
    generator.THUMB_DISTAL_MM = LONG_THUMB_MM
    try:
        urdf = generator.build().write(folder / "long_thumb.urdf")
    finally:
        generator.THUMB_DISTAL_MM = published
    registry = Registry.from_entry_points()
    hand = replace(registry.get_hand("karlsruhe"), name="long_thumb", model_path=urdf)
    register_hand = hookimpl(lambda register: register(hand))  # the hookspec's argument name
    plugin = types.SimpleNamespace(graspframe_register_hands=register_hand)
    registry.add_plugin("long_thumb", plugin)
    return registry


def _plan(registry: Registry, grasp: HumanGrasp, hand: str = "long_thumb"):
    obj = registry.default_object_for(grasp)
    human_palm = reference_placement(obj, registry.get_hand("human").preshape_for(grasp))
    T_world_object = make_T(p=[0.55, 0.2, obj.half_height])
    hand_description = registry.get_hand(hand)
    return plan_grasp(
        PlanningTarget(grasp, human_palm.T_object_palm, T_world_object, hand_description, obj)
    )


def test_a_thin_disc_out_of_the_fingers_reach_is_refused_saying_why(registry):
    with pytest.raises(PlanningError) as error:
        _plan(registry, HumanGrasp.PRECISION_DISC)
    message = str(error.value)
    assert "\n" not in message
    assert "'kh_thumb_distal' reaches" in message  # the link, and how far below the palm
    assert "raises it" in message and "the 25 mm tall disc" in message
    assert "(with no table in the way: thumb, index, middle)" in message
    # The published thumb reaches it: the same grasp is planned as the human has it.
    plan = _plan(registry, HumanGrasp.PRECISION_DISC, hand="karlsruhe")
    assert plan.reach == "" and len(plan.fingers_on_object) >= 2


def test_a_ball_under_the_long_thumb_is_approached_another_way(registry):
    # As the human palm has it, the hand is raised until only the thumb reaches the
    # ball; tilted, the fingers reach it again (the simulator then decides whether the
    # grasp holds: taken above its equator, this ball slips out when lifted).
    plan = _plan(registry, HumanGrasp.POWER_SPHERE)
    assert plan.reach  # planned otherwise than the human palm, and saying how
    assert set(plan.fingers_on_object) >= set(plan.fingers_without_table)
    assert not plan.open_inside_object and plan.lowest_touch_height > 0.0


def test_check_hand_reports_every_raise(registry):
    grasp = HumanGrasp.POWER_SPHERE
    hand = registry.get_hand("long_thumb")
    obj = registry.default_object_for(grasp)
    human_palm = reference_placement(obj, registry.get_hand("human").preshape_for(grasp))
    T_world_object = make_T(p=[0, 0, obj.half_height])
    checked = floating_plan(
        PlanningTarget(grasp, human_palm.T_object_palm, T_world_object, hand, obj)
    )
    trial = HoldTrial(grasp, "sphere", obj, ("thumb",), _unplanned(obj, ""), (), checked)
    lines = _plan_lines(trial)
    assert lines[0].startswith(f"goal raised {1000 * checked.plan.table_raise:.0f} mm")
    assert "lowest: link" in lines[0]
    assert any("planned instead with" in line for line in lines)
    assert lines[-1].startswith("real fingers on the object, closed without physics:")
    assert np.isfinite(checked.plan.lowest_below_palm)
