"""The static table and the graspable object as SAPIEN actors."""

from __future__ import annotations

import numpy as np
import sapien
from numpy.typing import NDArray

from graspframe.defaults import TABLE_HALF_SIZE
from graspframe.hal.objects import ObjectDescription
from graspframe_sapien.poses import to_pose

TABLE_FRICTION = (0.6, 0.5)  # static, dynamic [-]

# SAPIEN's cylinder axis is its local x; object cylinders stand along the object's z.
_X_TO_Z = sapien.Pose(q=[np.sqrt(0.5), 0.0, -np.sqrt(0.5), 0.0])


def build_table(scene: sapien.Scene, centre_xy: NDArray[np.float64], height: float):
    """A static box whose top face is at `height` [m], centred under `centre_xy`."""
    builder = scene.create_actor_builder()
    material = sapien.physx.PhysxMaterial(*TABLE_FRICTION, 0.0)
    builder.add_box_collision(half_size=TABLE_HALF_SIZE, material=material)
    table = builder.build_static(name="table")
    table.set_pose(sapien.Pose([centre_xy[0], centre_xy[1], height - TABLE_HALF_SIZE[2]]))
    return table


def build_object(scene: sapien.Scene, obj: ObjectDescription, T_world_object):
    """A dynamic actor of the object's shape, exact mass, friction; frame at its centroid."""
    builder = scene.create_actor_builder()
    material = sapien.physx.PhysxMaterial(
        obj.static_friction, obj.dynamic_friction, obj.restitution
    )
    density = obj.mass / obj.volume  # uniform density gives exactly obj.mass
    half_x, _, half_z = obj.half_extents
    if obj.shape == "box":
        builder.add_box_collision(half_size=obj.half_extents, material=material, density=density)
    elif obj.shape == "cylinder":
        builder.add_cylinder_collision(
            pose=_X_TO_Z, radius=half_x, half_length=half_z, material=material, density=density
        )
    else:
        builder.add_sphere_collision(radius=half_x, material=material, density=density)
    actor = builder.build(name=obj.name)
    actor.set_pose(to_pose(T_world_object))
    return actor
