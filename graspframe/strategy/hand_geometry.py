"""Geometry of a hand's preshapes, from its model: how deep the fingers reach.

`closing_sweep_depth` is the deepest point below the palm surface (along the palm normal)
that any finger shape reaches while the hand closes from the open to the closed
preshape in free space. A hand whose fingers pass through "upright" while closing (the
Barrett's) reaches deeper than its open palm-to-fingertip distance delta; a top grasp
must keep that depth above the table.
"""

from __future__ import annotations

import functools

import numpy as np

from graspframe.grasps import PALM
from graspframe.hal.descriptions import HandDescription
from graspframe.robot_model import CollisionModel
from graspframe.transforms import inv_T

SWEEP_SAMPLES = 16  # configurations between open and closed
_CIRCLE = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False)


def _shape_points(shape, T) -> np.ndarray:
    """Points bounding a box, cylinder or sphere, in the frame T maps into."""
    kind = type(shape).__name__
    if kind == "Box":
        half = np.asarray(shape.halfSide)
        local = (
            np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
        )
    elif kind == "Cylinder":
        ring = np.stack([np.cos(_CIRCLE), np.sin(_CIRCLE)], axis=1) * shape.radius
        local = np.concatenate(
            [np.c_[ring, np.full(len(ring), z)] for z in (-shape.halfLength, shape.halfLength)]
        )
    else:  # sphere: its extreme points along the frame's axes
        local = np.concatenate([np.eye(3), -np.eye(3)]) * shape.radius
        return local + T[:3, 3]
    return local @ T[:3, :3].T + T[:3, 3]


@functools.lru_cache(maxsize=64)
def _sweep_depth(model_path: str, palm_frame: str, finger_links: frozenset, configs) -> float:
    model = CollisionModel(model_path)
    depth = 0.0
    for q in configs:
        model.place(dict(q))
        T_palm_root = inv_T(model.T_root_frame(palm_frame))
        for link, shape, T_root_shape in model.shapes():
            if link in finger_links:
                points = _shape_points(shape, T_palm_root @ T_root_shape)
                depth = max(depth, float(points[:, 2].max()))
    return depth


def closing_sweep_depth(hand: HandDescription, preshape_name: str) -> float:
    """[m] deepest reach of the fingers below the palm surface while closing."""
    preshape = hand.preshape(preshape_name)
    configs = []
    for s in np.linspace(0.0, 1.0, SWEEP_SAMPLES):
        q = {
            name: (1 - s) * preshape.open_q.get(name, 0.0) + s * closed
            for name, closed in preshape.closed_q.items()
        }
        configs.append(tuple(sorted(hand.with_model_followers(q).items())))
    finger_links = frozenset(
        link for finger, links in hand.real_fingers.items() if finger != PALM for link in links
    )
    return _sweep_depth(str(hand.model_path), hand.palm_frame, finger_links, tuple(configs))
