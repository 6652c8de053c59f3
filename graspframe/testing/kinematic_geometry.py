"""Geometry of the kinematic test world: a robot's collision shapes placed by forward
kinematics, and their signed distances to the object (coal, on the URDF primitives and
the object's primitive or convex pieces)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.transforms import as_pose
from graspframe.hal.descriptions import HandDescription
from graspframe.hal.objects import ObjectDescription
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.motion.collision import object_obstacle
from graspframe.robot_models.model import CollisionModel


@dataclass(frozen=True)
class ShapeDistance:
    """One hand shape against the object.

    distance: [m] signed (negative: penetration depth).
    p_world: the object's point nearest to the shape [m].
    n_world: unit normal pointing from the object into the hand.
    """

    link: str
    distance: float
    p_world: NDArray[np.float64]
    n_world: NDArray[np.float64]


class KinematicGeometry:
    """The shapes of one model (a hand, or a hand mounted on an arm) and the object.

    model: the robot model; its root link is at `T_world_root`. Joints are set by name with
    `place`; followers of the hand's in-model couplings are set from their leaders.
    """

    def __init__(
        self,
        model: UrdfModel,
        hand: HandDescription,
        obj: ObjectDescription | None,
        T_world_object: NDArray[np.float64],
    ):
        import coal

        self._coal = coal
        self.hand = hand
        self.model = CollisionModel(model)
        finger_of_link = hand.finger_of_link()
        self.hand_shapes = tuple(
            i for i, link in enumerate(self.model.link_of_shape) if link in finger_of_link
        )
        self.T_world_root = np.eye(4)
        self.object_shapes: list = []
        if obj is not None:
            self.object_shapes = object_obstacle(obj, np.eye(4)).collision_geometries()
        self.T_world_object = as_pose(T_world_object, "T_world_object")
        self._request = coal.DistanceRequest()
        self._request.enable_signed_distance = True

    def place(self, q_by_joint: Mapping[str, float]) -> None:
        """Set the model's joints [rad] (hand followers added) and place its shapes."""
        self.model.place(self.hand.with_model_followers(q_by_joint))

    def T_world_frame(self, frame: str) -> NDArray[np.float64]:
        """Pose of a link or frame of the placed model in the world."""
        return self.T_world_root @ self.model.T_root_frame(frame)

    def shapes_moved_by(self, joint: str) -> tuple[int, ...]:
        """Hand shapes that `joint` moves: its subtree and those of its in-model followers."""
        pin_model = self.model.model
        joints = [joint] + [
            c.follower for c in self.hand.couplings if c.in_model and c.leader == joint
        ]
        moved: set[int] = set()
        for name in joints:
            moved.update(pin_model.subtrees[pin_model.getJointId(name)])
        geometry = self.model.geometry.geometryObjects
        return tuple(i for i in self.hand_shapes if geometry[i].parentJoint in moved)

    def distances(self, shapes: Sequence[int] | None = None) -> list[ShapeDistance]:
        """Signed distances of the placed hand shapes (default: all) to the object (the
        nearest of its shapes)."""
        if not self.object_shapes:
            return []
        coal = self._coal
        R_object, p_object = self.T_world_object[:3, :3], self.T_world_object[:3, 3]
        tf_object = coal.Transform3s(R_object, p_object)
        found = []
        for index in self.hand_shapes if shapes is None else shapes:
            T_world_shape = self.T_world_root @ self.model.geometry_data.oMg[index].homogeneous
            tf_shape = coal.Transform3s(T_world_shape[:3, :3], T_world_shape[:3, 3])
            hand_shape = self.model.geometry.geometryObjects[index].geometry
            distance, result = np.inf, None
            for object_shape in self.object_shapes:
                candidate = coal.DistanceResult()
                d = coal.distance(
                    hand_shape, tf_shape, object_shape, tf_object, self._request, candidate
                )
                if d < distance:
                    distance, result = d, candidate
            assert result is not None
            found.append(
                ShapeDistance(
                    link=self.model.link_of_shape[index],
                    distance=float(distance),
                    p_world=np.array(result.getNearestPoint2(), dtype=float),
                    # coal's normal points from the first shape (the hand) to the second.
                    n_world=-np.array(result.normal, dtype=float),
                )
            )
        return found

    def min_distance(self, shapes: Sequence[int]) -> float:
        """[m] the smallest signed distance of these hand shapes to the object (inf: none)."""
        return min((d.distance for d in self.distances(shapes)), default=np.inf)
