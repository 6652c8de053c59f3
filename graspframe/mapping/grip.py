"""What a candidate's predicted contacts (graspframe/mapping/candidates.py, object frame,
the object standing on the table: its z is the world's up) say about the grip: which
touches grip at all, how unbalanced their push is, and their Ferrari-Canny epsilon."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from graspframe.common.contacts import Contact
from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import PALM
from graspframe.hal.objects import ObjectDescription

# A touch whose surface normal lies within this of the world's up is on a face that looks
# up: a finger there presses the object into the table (and slides off its edge as it
# closes further, tipping a flat object), it holds nothing once the object is lifted.
TOP_FACE_ANGLE = math.radians(30.0)


def gripping(contacts: Sequence[Contact]) -> list[Contact]:
    """The contacts that can grip: not a finger's touch on a face that looks up (the
    palm's is kept: a volar grasp presses the palm on the object)."""
    cos_top = math.cos(TOP_FACE_ANGLE)
    return [
        c
        for c in contacts
        if c.real_finger == PALM
        or float(np.asarray(c.n, dtype=float)[2]) < cos_top * float(np.linalg.norm(c.n))
    ]


def imbalance(contacts: Sequence[Contact]) -> float:
    """How much the contacts, each pushing with a unit force along its normal into the
    object, push it one way: |sum of the forces| / their count (0: they balance, 1: all
    push the same way), the table taking what pushes the object down (object frame z is
    the world's up for an object standing on it)."""
    forces = np.array([c.f for c in contacts], dtype=float).reshape(-1, 3)
    forces /= np.maximum(np.linalg.norm(forces, axis=1, keepdims=True), 1e-12)
    net = forces.sum(axis=0)
    net[2] = max(net[2], 0.0)
    return float(np.linalg.norm(net) / max(len(forces), 1))


def epsilon_of(contacts: Sequence[Contact], obj: ObjectDescription) -> float:
    """The contacts' (object frame) Ferrari-Canny L1 epsilon, as every run scores its
    grasp: the object's static friction, torques about its centroid over its half
    largest dimension; 0 when the contacts do not close the grasp."""
    from graspframe.metrics.quality import grasp_quality

    try:
        quality = grasp_quality(
            [c.p for c in contacts],
            [-np.asarray(c.n) for c in contacts],  # the contact normals point out
            obj.static_friction,
            torque_length=obj.largest_dimension / 2,
        )
    except GraspframeError:
        return 0.0
    return quality.epsilon_l1
