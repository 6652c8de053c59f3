"""Object geometry on ObjectDescription: extents, half height, volume, symmetry."""

from __future__ import annotations

import math

import pytest

from graspframe.hal.objects import ObjectDescription

BOX = ObjectDescription("box", "box", {"size_x": 0.04, "size_y": 0.06, "size_z": 0.1}, mass=0.2)
CAN = ObjectDescription("can", "cylinder", {"radius": 0.03, "length": 0.12}, mass=0.3)
BALL = ObjectDescription("ball", "sphere", {"radius": 0.025}, mass=0.1)


def test_half_extents_and_what_follows_from_them():
    assert BOX.half_extents == pytest.approx((0.02, 0.03, 0.05))
    assert CAN.half_extents == pytest.approx((0.03, 0.03, 0.06))
    assert BALL.half_extents == pytest.approx((0.025,) * 3)
    assert [o.half_height for o in (BOX, CAN, BALL)] == pytest.approx([0.05, 0.06, 0.025])
    assert [o.largest_dimension for o in (BOX, CAN, BALL)] == pytest.approx([0.1, 0.12, 0.05])


def test_extent_along_a_direction():
    assert BOX.extent_along((1.0, 0.0, 0.0)) == pytest.approx(0.02)
    assert BOX.extent_along((0.0, -1.0, 1.0)) == pytest.approx((0.03 + 0.05) / math.sqrt(2))
    assert CAN.extent_along((0.0, 0.0, -2.0)) == pytest.approx(0.06)
    assert CAN.extent_along((1.0, 1.0, 0.0)) == pytest.approx(0.03)
    assert BALL.extent_along((0.3, -0.2, 0.9)) == pytest.approx(0.025)


def test_volume_and_symmetry():
    assert BOX.volume == pytest.approx(0.04 * 0.06 * 0.1)
    assert CAN.volume == pytest.approx(math.pi * 0.03**2 * 0.12)
    assert BALL.volume == pytest.approx(4 / 3 * math.pi * 0.025**3)
    assert not BOX.symmetric_about_z
    assert CAN.symmetric_about_z and BALL.symmetric_about_z
