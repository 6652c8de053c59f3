"""What predicted contacts say about the grip (graspframe/mapping/grip.py): a finger's
touch on a face that looks up holds nothing, the palm's and a side touch do; fingers
that all push one way are unbalanced; contacts that close the grasp have an epsilon."""

from __future__ import annotations

import math

import numpy as np
import pytest

from graspframe.common.contacts import OBJECT, Contact
from graspframe.common.grasps import PALM
from graspframe.hal.objects import ObjectDescription
from graspframe.mapping.grip import TOP_FACE_ANGLE, epsilon_of, gripping, imbalance

DISC = ObjectDescription("disc", "cylinder", {"radius": 0.045, "length": 0.025}, mass=0.1)


def _touch(finger: str, p, n) -> Contact:
    """A touch at p [m] (object frame) where the surface's outward normal is n."""
    n = np.asarray(n, dtype=float) / np.linalg.norm(n)
    return Contact(finger, finger, np.asarray(p, dtype=float), n, -n, frame=OBJECT)


def test_a_finger_on_a_face_that_looks_up_does_not_grip_and_the_palm_does():
    just_steeper = math.radians(math.degrees(TOP_FACE_ANGLE) + 1.0)
    side = _touch("index", (0.045, 0, 0), (1, 0, 0))
    top = _touch("middle", (0.02, 0, 0.0125), (0, 0, 1))
    rim = _touch("ring", (0.044, 0, 0.012), (math.sin(just_steeper), 0, math.cos(just_steeper)))
    palm = _touch(PALM, (0, 0, 0.0125), (0, 0, 1))
    kept = gripping([side, top, rim, palm])
    assert [c.real_finger for c in kept] == ["index", "ring", PALM]


def test_touches_round_the_object_balance_and_close_the_grasp_and_one_side_does_not():
    thumb = _touch("thumb", (-0.045, 0, 0), (-1, 0, 0))
    index = _touch("index", (0.0318, 0.0318, 0), (1, 1, 0))
    middle = _touch("middle", (0.0318, -0.0318, 0), (1, -1, 0))
    ring = _touch("ring", (0.045, 0, 0), (1, 0, 0))
    assert imbalance([thumb, ring]) == pytest.approx(0.0, abs=1e-12)
    assert imbalance([index, ring]) > 0.9
    # three touches round the disc close the grasp; three on one side do not
    assert epsilon_of([thumb, index, middle], DISC) > 0.0
    assert epsilon_of([index, middle, ring], DISC) == 0.0
