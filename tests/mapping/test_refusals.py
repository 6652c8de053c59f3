"""The synthesis's refusals (graspframe/mapping/refusals.py) on the built-in Barrett
hand's model: a finger in the way of the approach is found, a clear approach is not;
open links that overlap are found, apart ones are not."""

from __future__ import annotations

import numpy as np

from graspframe.common.transforms import make_T
from graspframe.hal.objects import ObjectDescription
from graspframe.mapping.refusals import self_collisions
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.strategy.hand_geometry import approach_touch

BARRETT = default_registry().get_hand("barrett")
UP_PALM = np.array([0.0, 0.0, 1.0])  # the approach along the palm normal (palm frame)


def _open_q(proximal_rad: float = 1.2) -> dict[str, float]:
    """The Barrett open with its fingers raised off the palm (at 0 they lie flat), the
    tips 103 mm out along the palm normal and 58 mm off its centre."""
    q = {name: 0.0 for name in BARRETT.joint_names}
    q.update({name: proximal_rad for name in q if name.endswith("_prox")})
    return q


def _at_palm(height: float) -> np.ndarray:
    """T_palm_object: the object's centre `height` [m] out along the palm normal."""
    return make_T(np.eye(3), (0.0, 0.0, height))


def test_a_ball_wider_than_the_open_fingers_is_touched_by_a_finger_on_the_approach():
    ball = ObjectDescription("ball", "sphere", {"radius": 0.06}, mass=0.1)
    touch = approach_touch(BARRETT, _open_q(), ball, _at_palm(0.063), UP_PALM, 0.15)
    assert touch is not None
    finger, d = touch
    assert finger in BARRETT.finger_names
    assert 0.0 < d <= 0.15


def test_a_thin_rod_between_the_open_fingers_reaches_the_palm_untouched():
    # a rod along the palm normal through the palm centre, between the three fingers
    rod = ObjectDescription("rod", "cylinder", {"radius": 0.004, "length": 0.05}, mass=0.01)
    assert approach_touch(BARRETT, _open_q(), rod, _at_palm(0.03), UP_PALM, 0.15) is None


def test_open_links_that_overlap_are_found_and_apart_ones_are_not():
    model = CollisionModel(model_of(BARRETT))
    apart = BARRETT.with_model_followers(_open_q())
    assert self_collisions(model, [apart, apart]) == ([], [])
    # every finger joint at its upper limit: the fingers fold into each other
    folded = {j.name: j.upper for j in BARRETT.joints}
    opened, closed_only = self_collisions(model, [BARRETT.with_model_followers(folded), apart])
    assert opened, "the folded Barrett's fingers overlap"
    assert closed_only == []
