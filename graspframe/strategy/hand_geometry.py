"""Geometry of a hand's preshapes, from its model: how low the hand reaches.

`closing_configurations` closes a preshape kinematically on an object: every real finger
moves from the open to the closed targets together and stops at the first sample where
one of its links touches the object (Pinocchio places the shapes, coal tests them
against the object's primitive, or a mesh object's convex pieces). This is the hand's
shape at every moment of a grasp, without a simulator.

`lowest_points` is the lowest point, along the world vertical, of every hand link's
shapes (palm included) over those configurations, relative to the palm origin, for a
given palm orientation: a goal must keep them above the table. `approach_touch` is the
first finger the open hand brings onto the object on its way to the goal. `fingertip_links` names
each real finger's last shaped link (a planner alternative lets only those come nearer
the table).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from graspframe.common.grasps import PALM
from graspframe.common.transforms import inv_T
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.objects import ObjectDescription
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.robot_models.shapes import object_coal_geometries

SWEEP_SAMPLES = 16  # configurations between open and closed


@functools.lru_cache(maxsize=16)
def _collision_model(model: UrdfModel) -> CollisionModel:
    return CollisionModel(model)


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


class ClosingSweep(NamedTuple):
    """A preshape closed kinematically: configurations: hand joint values [rad]
    (followers included) from open to closed; touched: the real fingers (not the palm)
    that stopped on the object, in the order they touched it; open_inside: the links
    that lie in the object in the open posture (the approach would push it);
    p_object_touch: (N, 3) [m] where each of them first touched it, object frame (a
    point of the shapes' overlap); finger_touch: (N,) the real finger of each;
    s_touch: (N,) how far through the closing (0 open, 1 closed) each touched."""

    configurations: list[dict[str, float]]
    touched: tuple[str, ...]
    open_inside: tuple[str, ...] = ()
    p_object_touch: NDArray[np.float64] = np.zeros((0, 3))
    finger_touch: tuple[str, ...] = ()
    s_touch: tuple[float, ...] = ()


def closing_sweep(
    hand: HandDescription,
    preshape: HandPreshape,
    obj: ObjectDescription | None = None,
    T_palm_object: NDArray[np.float64] | None = None,
    samples: int = SWEEP_SAMPLES,
) -> ClosingSweep:
    """The preshape from open to closed; with an object at T_palm_object, each real
    finger stops where one of its links first touches it."""
    import coal

    model = _collision_model(model_of(hand))
    finger_joints = _joints_of_fingers(hand, model)
    finger_of_link = hand.finger_of_link()
    geometries: list = []
    if obj is not None and T_palm_object is not None:
        geometries = object_coal_geometries(obj)
        model.place(hand.with_model_followers(dict(preshape.open_q)))
        T_root_object = model.T_root_frame(hand.palm_frame) @ T_palm_object
        T_object_root = inv_T(T_root_object)
        tf_object = coal.Transform3s(T_root_object[:3, :3], T_root_object[:3, 3])
    frozen: dict[str, float] = {}
    stopped: list[str] = []
    open_inside: list[str] = []
    touch_points: list[NDArray[np.float64]] = []
    touch_fingers: list[str] = []
    touch_s: list[float] = []
    configurations = []
    previous: dict[str, float] | None = None
    for s in np.linspace(0.0, 1.0, samples):
        q = hand.with_model_followers(_interpolate(preshape, float(s), frozen))
        if geometries and s == 0.0:
            open_inside = _links_inside(model, q, geometries, tf_object)
        if geometries and s > 0.0:
            model.place(q)
            touching = set()
            for link, shape, T_root_shape in model.shapes():
                finger = finger_of_link.get(link)
                if finger is None or finger == PALM or finger in stopped:
                    continue
                tf = coal.Transform3s(T_root_shape[:3, :3], T_root_shape[:3, 3])
                for geometry in geometries:
                    request, result = coal.CollisionRequest(), coal.CollisionResult()
                    if coal.collide(shape, tf, geometry, tf_object, request, result):
                        touching.add(finger)
                        p_root = np.asarray(result.getContact(0).pos, dtype=float)
                        touch_points.append(T_object_root @ np.append(p_root, 1.0))
                        touch_fingers.append(finger)
                        touch_s.append(float(s))
                        break
            for finger in sorted(touching):
                stopped.append(finger)
                for name in finger_joints.get(finger, []):
                    frozen[name] = previous[name] if previous else q[name]
            if touching:
                q = hand.with_model_followers(_interpolate(preshape, float(s), frozen))
        configurations.append(q)
        previous = q
    points = np.array([p[:3] for p in touch_points]).reshape(-1, 3)
    return ClosingSweep(
        configurations,
        tuple(stopped),
        tuple(open_inside),
        points,
        tuple(touch_fingers),
        tuple(touch_s),
    )


def _links_inside(model: CollisionModel, q: dict[str, float], geometries: list, tf_object) -> list:
    """The links with a shape in the object (coal collision) at hand joints q."""
    import coal

    model.place(q)
    inside: list[str] = []
    for link, shape, T_root_shape in model.shapes():
        if link in inside:
            continue
        tf = coal.Transform3s(T_root_shape[:3, :3], T_root_shape[:3, 3])
        for geometry in geometries:
            if coal.collide(
                shape, tf, geometry, tf_object, coal.CollisionRequest(), coal.CollisionResult()
            ):
                inside.append(link)
                break
    return inside


APPROACH_STEP = 0.01  # [m] between the positions approach_touch tests


def approach_touch(
    hand: HandDescription,
    open_q: Mapping[str, float],
    obj: ObjectDescription,
    T_palm_object: NDArray[np.float64],
    a_palm: NDArray[np.float64],
    distance: float,
) -> tuple[str, float] | None:
    """(the real finger, how far before the goal [m]) that first touches the object when
    the hand, open, comes `distance` along the unit approach direction a_palm (palm
    frame) to T_palm_object, the goal; None when no finger touches before the goal (the
    palm may: it is meant to). Tested every APPROACH_STEP, from the far end."""
    import coal

    model = _collision_model(model_of(hand))
    model.place(hand.with_model_followers(dict(open_q)))
    geometries = object_coal_geometries(obj)
    finger_of_link = hand.finger_of_link()
    fingers = [
        (finger, shape, T_root_shape)
        for link, shape, T_root_shape in model.shapes()
        if (finger := finger_of_link.get(link)) not in (None, PALM)
    ]
    T_root_palm = model.T_root_frame(hand.palm_frame)
    steps = max(round(distance / APPROACH_STEP), 1)
    for d in np.linspace(distance, 0.0, steps + 1)[:-1]:
        T_shifted = T_palm_object.copy()
        T_shifted[:3, 3] += d * np.asarray(a_palm, dtype=float)
        T_root_object = T_root_palm @ T_shifted
        tf_object = coal.Transform3s(T_root_object[:3, :3], T_root_object[:3, 3])
        for finger, shape, T_root_shape in fingers:
            tf = coal.Transform3s(T_root_shape[:3, :3], T_root_shape[:3, 3])
            for geometry in geometries:
                request, result = coal.CollisionRequest(), coal.CollisionResult()
                if coal.collide(shape, tf, geometry, tf_object, request, result):
                    return finger, float(d)
    return None


def closing_configurations(
    hand: HandDescription,
    preshape: HandPreshape,
    obj: ObjectDescription | None = None,
    T_palm_object: NDArray[np.float64] | None = None,
    samples: int = SWEEP_SAMPLES,
) -> list[dict[str, float]]:
    """Hand joint values [rad] (followers included) from open to closed; with an object
    at T_palm_object, each real finger stops where one of its links first touches it."""
    return closing_sweep(hand, preshape, obj, T_palm_object, samples).configurations


def lowest_points(
    hand: HandDescription,
    configurations: list[dict[str, float]],
    R_world_palm: NDArray[np.float64],
) -> dict[str, float]:
    """link -> [m] the lowest world height of its shapes over the configurations,
    relative to the palm origin (negative: below it), the palm turned by R_world_palm."""
    model = _collision_model(model_of(hand))
    lowest: dict[str, float] = {}
    for q in configurations:
        model.place(q)
        T_palm_root = inv_T(model.T_root_frame(hand.palm_frame))
        for index, (link, shape, T_root_shape) in enumerate(model.shapes()):
            T_palm_shape = T_palm_root @ T_root_shape
            points_palm = model.local_points(index) @ T_palm_shape[:3, :3].T + T_palm_shape[:3, 3]
            if type(shape).__name__ == "Sphere":  # lowest point of a sphere is exact
                centre_world_z = float((R_world_palm @ points_palm.mean(axis=0))[2])
                height = centre_world_z - shape.radius
            else:
                height = float((points_palm @ R_world_palm.T)[:, 2].min())
            lowest[link] = min(lowest.get(link, np.inf), height)
    return lowest


def fingertip_links(hand: HandDescription) -> dict[str, str]:
    """real finger (not the palm) -> its fingertip: its shaped link furthest down the
    kinematic chain."""
    model = _collision_model(model_of(hand))
    shaped = {link for link, _shape, _T in model.shapes()}

    def depth(link: str) -> int:
        n, parent = 0, model.parent_link(link)
        while parent is not None:
            n, parent = n + 1, model.parent_link(parent)
        return n

    tips = {}
    for finger, links in hand.real_fingers.items():
        candidates = [link for link in links if link in shaped]
        if finger != PALM and candidates:
            tips[finger] = max(candidates, key=depth)
    return tips
