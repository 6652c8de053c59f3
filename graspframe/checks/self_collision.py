"""Contract check: every preshape's open posture is free of self-collision.

The hand opens into its preshape before it reaches the object, so no two of its links may
overlap there. Two kinds of pair may meet by design and are not counted: adjacent links
(a joint joins them) and links fixed to each other (no movable joint between them: a pad
sunk into the palm it sits on overlaps it in every posture). Collision shapes are placed
by Pinocchio, overlaps and distances measured by coal. The simulator runs without
self-collision, so only this check sees an overlap.
"""

from __future__ import annotations

import math

from graspframe.common.errors import GraspframeError
from graspframe.hal.descriptions import HandDescription
from graspframe.robot_models.model import CollisionModel, model_of


def signed_link_distance(model: CollisionModel, link_a: str, link_b: str) -> float:
    """[m] smallest signed distance between the shapes of two links at the placed
    posture: negative when they overlap (the depth of the deepest overlap)."""
    import coal

    placed = list(model.shapes())
    best = math.inf
    for shape_link_a, shape_a, T_root_a in placed:
        if shape_link_a != link_a:
            continue
        for shape_link_b, shape_b, T_root_b in placed:
            if shape_link_b != link_b:
                continue
            distance = coal.distance(
                shape_a,
                coal.Transform3s(T_root_a[:3, :3], T_root_a[:3, 3]),
                shape_b,
                coal.Transform3s(T_root_b[:3, :3], T_root_b[:3, 3]),
                coal.DistanceRequest(),
                coal.DistanceResult(),
            )
            best = min(best, float(distance))
    return best


def _fixed_to_each_other(model: CollisionModel, link_a: str, link_b: str) -> bool:
    """True when no movable joint lies between the two links (Pinocchio hangs both
    from the same joint)."""
    frames = model.model.frames
    joint_a = frames[model.model.getFrameId(link_a)].parentJoint
    return bool(joint_a == frames[model.model.getFrameId(link_b)].parentJoint)


def posture_collisions(
    model: CollisionModel, q_by_joint: dict[str, float]
) -> list[tuple[str, str]]:
    """The pairs of links that overlap or touch with the model placed at q_by_joint
    (every joint the model has, followers included), pairs meant to meet left out."""
    model.place(q_by_joint)
    return [
        (link_a, link_b)
        for link_a, link_b in model.colliding_links()
        if not _fixed_to_each_other(model, link_a, link_b)
    ]


def open_preshape_collisions(
    hand: HandDescription, model: CollisionModel
) -> dict[str, list[tuple[str, str, float]]]:
    """Preshape name -> (link, link, signed distance [m]) of every pair of links that
    overlap or touch in its open posture (couplings followed), pairs meant to meet
    left out."""
    collisions: dict[str, list[tuple[str, str, float]]] = {}
    for preshape in hand.preshapes.values():
        pairs = posture_collisions(model, hand.with_model_followers(preshape.open_q))
        collisions[preshape.name] = [
            (link_a, link_b, signed_link_distance(model, link_a, link_b))
            for link_a, link_b in pairs
        ]
    return collisions


def self_collision_problems(hand: HandDescription) -> list[str]:
    """Every pair of links that overlaps or touches in a preshape's open posture, with
    its signed distance, in plain words."""
    try:
        model = CollisionModel(model_of(hand))
        collisions = open_preshape_collisions(hand, model)
    except GraspframeError as exc:
        return [str(exc)]
    return [
        f"preshape {name!r} open: links {link_a!r} and {link_b!r} collide (signed distance "
        f"{round(1000 * distance, 1) + 0.0:.1f} mm; move them apart in the open posture "
        "or in the model)"
        for name, pairs in collisions.items()
        for link_a, link_b, distance in pairs
    ]
