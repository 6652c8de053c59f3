"""A <mimic> leader's reachable range: the values of its own range that keep every
follower within the follower's range (q_follower = multiplier * q_leader + offset).

The Ability hand's index_q1 has [0, 2.09] rad, but its follower index_q2 = 1.06 q1 + 0.72
reaches its upper limit 2.66 at q1 = 1.83: the simulator stops the finger there, so a
kinematic closing that took the leader on to 2.09 would curl the finger further than it
can go."""

from __future__ import annotations

from collections.abc import Mapping


def leader_ranges(
    ranges: Mapping[str, tuple[float, float]],
    followers: Mapping[str, tuple[str, float, float]],
) -> dict[str, tuple[float, float]]:
    """ranges: joint -> (lower, upper) [rad or m]; followers: follower -> (leader,
    multiplier, offset). The ranges with each leader's cut to its followers' (a cut that
    leaves nothing keeps the leader's own range: the model's limits disagree, and the
    simulator's stop is not known)."""
    cut = dict(ranges)
    for follower, (leader, multiplier, offset) in followers.items():
        if leader not in cut or follower not in ranges or multiplier == 0.0:
            continue
        f_lower, f_upper = ranges[follower]
        ends = sorted(((f_lower - offset) / multiplier, (f_upper - offset) / multiplier))
        lower, upper = max(cut[leader][0], ends[0]), min(cut[leader][1], ends[1])
        if lower <= upper:
            cut[leader] = (lower, upper)
    return cut
