"""Why a candidate preshape of the synthesis (mapping/candidates.py) cannot be executed
as it is: a finger on the object before the palm reaches its goal, links of the hand
overlapping each other, the hand reaching into the table's clearance. Geometry only
(Pinocchio places the shapes, coal tests them), with the planner's own settings."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from graspframe.common.transforms import inv_T
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.objects import ObjectDescription
from graspframe.robot_models.model import CollisionModel
from graspframe.strategy.planner import PlannerParams, PlanningError


def approach_refusal(
    obj: ObjectDescription,
    hand: HandDescription,
    preshape: HandPreshape,
    T_palm_object: NDArray[np.float64],
) -> str | None:
    """Why the open hand cannot come to T_palm_object along the planner's approach (a
    finger reaches the object before the goal: the volar strategy backs off, a closing
    from the standoff starts off the object), or None. `obj` stands on the table."""
    from graspframe.strategy.hand_geometry import approach_touch
    from graspframe.strategy.planner import approach_direction

    params = PlannerParams()
    R_world_palm = obj.T_world_standing()[:3, :3] @ T_palm_object[:3, :3].T
    try:
        _kind, a_world = approach_direction(R_world_palm, params)
    except PlanningError as exc:
        return str(exc)
    a_palm = R_world_palm.T @ a_world
    touch = approach_touch(
        hand, preshape.open_q, obj, T_palm_object, a_palm, params.pre_approach_distance
    )
    if touch is None:
        return None
    finger, d = touch
    return f"on the approach, {finger} touches the object {1000 * d:.0f} mm before the goal"


def self_collisions(
    model: CollisionModel, configurations: list[dict[str, float]]
) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
    """(pairs of links that overlap in the open posture, the first configuration; pairs
    that overlap only where the fingers stop, the last): the simulator does not collide
    a hand with itself, only this sees them."""
    from graspframe.checks.self_collision import posture_collisions

    opened = posture_collisions(model, configurations[0])
    closed = posture_collisions(model, configurations[-1])
    return opened, [pair for pair in closed if pair not in opened]


def below_table(
    obj: ObjectDescription,
    hand: HandDescription,
    configurations: list[dict[str, float]],
    T_palm_object: NDArray[np.float64],
) -> tuple[str | None, float]:
    """(the link that comes deepest within the planner's table clearance of the table
    while the hand closes, how deep [m]): the planner would raise the hand off the
    object. (None, 0) when none does."""
    from graspframe.hal.objects import TABLE_HEIGHT
    from graspframe.strategy.hand_geometry import lowest_points

    T_world_palm = obj.T_world_standing() @ inv_T(T_palm_object)
    lowest = lowest_points(hand, configurations, T_world_palm[:3, :3])
    limit = TABLE_HEIGHT + PlannerParams().table_clearance - T_world_palm[2, 3]
    below = [link for link, z in lowest.items() if z < limit]
    if not below:
        return None, 0.0
    link = min(below, key=lambda name: lowest[name])
    return link, float(limit - lowest[link])
