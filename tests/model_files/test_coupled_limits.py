"""A <mimic> leader's range is cut to what its followers' ranges let it reach."""

from __future__ import annotations

import pytest

from graspframe.model_files.coupled_limits import leader_ranges


def test_a_follower_with_an_offset_stops_its_leader_short_of_its_own_limit():
    # the Ability hand's index finger: q2 = 1.0585 q1 + 0.7235, q2 at most 2.659 rad
    ranges = {"q1": (0.0, 2.0944), "q2": (0.0, 2.659)}
    cut = leader_ranges(ranges, {"q2": ("q1", 1.05851325, 0.72349796)})
    assert cut["q1"] == pytest.approx((0.0, (2.659 - 0.72349796) / 1.05851325))
    assert cut["q2"] == ranges["q2"]


def test_a_negative_multiplier_cuts_the_other_end_and_unlimiting_couplings_change_nothing():
    ranges = {"lead": (-1.0, 1.0), "mirror": (-0.5, 2.0), "twin": (-1.0, 1.0)}
    followers = {"mirror": ("lead", -1.0, 0.0), "twin": ("lead", 1.0, 0.0)}
    cut = leader_ranges(ranges, followers)
    assert cut["lead"] == pytest.approx((-1.0, 0.5))


def test_limits_that_leave_no_common_range_keep_the_leaders_own():
    ranges = {"lead": (0.0, 1.0), "follower": (5.0, 6.0)}
    assert leader_ranges(ranges, {"follower": ("lead", 1.0, 0.0)})["lead"] == (0.0, 1.0)
