"""Geometry of a hand's preshapes, from its model: how low the hand reaches.

`closing_configurations` closes a preshape kinematically on an object: every real finger
moves from the open to the closed targets together and stops at the first sample where
one of its links touches the object (Pinocchio places the shapes, coal tests them). This
is the hand's shape at every moment of a grasp, without a simulator.

`lowest_hand_point` is the lowest point, along the world vertical, of every hand shape
(palm included) over those configurations, relative to the palm origin, for a given palm
orientation: a goal must keep it above the table.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from graspframe.grasps import PALM
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.objects import ObjectDescription
from graspframe.robot_model import CollisionModel
from graspframe.transforms import inv_T

SWEEP_SAMPLES = 16  # configurations between open and closed
_CIRCLE = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False)


def shape_points(shape, T) -> np.ndarray:
    """Points bounding a box, cylinder or sphere, in the frame T maps into. A sphere
    gives its centre and its extreme points along that frame's axes (exact for the
    lowest point along any of those axes)."""
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


@functools.lru_cache(maxsize=16)
def _collision_model(model_path: str) -> CollisionModel:
    return CollisionModel(model_path)


def _object_geometry(obj: ObjectDescription):
    """The object as a coal shape, and the transform from the object frame to it (coal
    cylinders are along their z, like the object's axis)."""
    import coal

    d = obj.dimensions
    if obj.shape == "box":
        return coal.Box(d["size_x"], d["size_y"], d["size_z"])
    if obj.shape == "cylinder":
        return coal.Cylinder(d["radius"], d["length"])
    return coal.Sphere(d["radius"])


def _interpolate(preshape: HandPreshape, s: float, frozen: Mapping[str, float]) -> dict:
    q = {
        name: (1 - s) * preshape.open_q.get(name, 0.0) + s * closed
        for name, closed in preshape.closed_q.items()
    }
    q.update(frozen)
    return q


def _joints_of_fingers(hand: HandDescription, model: CollisionModel) -> dict[str, list[str]]:
    """real finger -> the driven joints that move one of its links directly."""
    finger_of_link = hand.finger_of_link()
    joints: dict[str, list[str]] = {}
    for name in hand.joint_names:
        joint_id = model.model.getJointId(name)
        child_links = [
            f.name
            for f in model.model.frames
            if f.parentJoint == joint_id and f.name in finger_of_link
        ]
        for link in child_links:
            joints.setdefault(finger_of_link[link], [])
            if name not in joints[finger_of_link[link]]:
                joints[finger_of_link[link]].append(name)
    return joints


def closing_configurations(
    hand: HandDescription,
    preshape: HandPreshape,
    obj: ObjectDescription | None = None,
    T_palm_object: NDArray[np.float64] | None = None,
    samples: int = SWEEP_SAMPLES,
) -> list[dict[str, float]]:
    """Hand joint values [rad] (followers included) from open to closed; with an object
    at T_palm_object, each real finger stops where one of its links first touches it."""
    import coal

    model = _collision_model(str(hand.model_path))
    finger_joints = _joints_of_fingers(hand, model)
    finger_of_link = hand.finger_of_link()
    geometry = None
    if obj is not None and T_palm_object is not None:
        geometry = _object_geometry(obj)
        model.place(hand.with_model_followers(dict(preshape.open_q)))
        T_root_object = model.T_root_frame(hand.palm_frame) @ T_palm_object
        tf_object = coal.Transform3s(T_root_object[:3, :3], T_root_object[:3, 3])
    frozen: dict[str, float] = {}
    stopped: set[str] = set()
    configurations = []
    previous: dict[str, float] | None = None
    for s in np.linspace(0.0, 1.0, samples):
        q = hand.with_model_followers(_interpolate(preshape, float(s), frozen))
        if geometry is not None and s > 0.0:
            model.place(q)
            touching = set()
            for link, shape, T_root_shape in model.shapes():
                finger = finger_of_link.get(link)
                if finger is None or finger == PALM or finger in stopped:
                    continue
                tf = coal.Transform3s(T_root_shape[:3, :3], T_root_shape[:3, 3])
                request, result = coal.CollisionRequest(), coal.CollisionResult()
                if coal.collide(shape, tf, geometry, tf_object, request, result):
                    touching.add(finger)
            for finger in touching:
                stopped.add(finger)
                for name in finger_joints.get(finger, []):
                    frozen[name] = previous[name] if previous else q[name]
            if touching:
                q = hand.with_model_followers(_interpolate(preshape, float(s), frozen))
        configurations.append(q)
        previous = q
    return configurations


def lowest_hand_point(
    hand: HandDescription,
    configurations: list[dict[str, float]],
    R_world_palm: NDArray[np.float64],
) -> float:
    """[m] the lowest world height of any hand shape over the configurations, relative
    to the palm origin (negative: below it), with the palm turned by R_world_palm."""
    model = _collision_model(str(hand.model_path))
    lowest = np.inf
    for q in configurations:
        model.place(q)
        T_palm_root = inv_T(model.T_root_frame(hand.palm_frame))
        for _link, shape, T_root_shape in model.shapes():
            points_palm = shape_points(shape, T_palm_root @ T_root_shape)
            if type(shape).__name__ == "Sphere":  # lowest point of a sphere is exact
                centre_world_z = float((R_world_palm @ points_palm.mean(axis=0))[2])
                lowest = min(lowest, centre_world_z - shape.radius)
                continue
            lowest = min(lowest, float((points_palm @ R_world_palm.T)[:, 2].min()))
    return float(lowest)
