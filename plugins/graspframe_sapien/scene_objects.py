"""The static table and the graspable object as SAPIEN actors."""

from __future__ import annotations

import numpy as np
import sapien
from numpy.typing import NDArray

from graspframe.common.defaults import TABLE_HALF_SIZE
from graspframe.common.errors import GraspframeError
from graspframe.common.transforms import quat_wxyz_from_R
from graspframe.hal.objects import ObjectDescription
from graspframe_sapien.poses import to_pose

TABLE_FRICTION = (0.6, 0.5)  # static, dynamic [-]
# PhysX builds its own hull of each convex piece when it cooks it and drops the points it
# finds within its plane tolerance (0.7 mm) of the hull under construction; the pieces
# (graspframe/model_files/convex.py) keep no vertex within 1 mm of the others' hull, and on the
# YCB scans PhysX still drops a vertex of 5 of 359 pieces, moving their surface inward
# by at most 1.9 mm (tests/plugins/ycb/test_ycb_objects.py). A larger change is refused.
MAX_COOKING_CHANGE = 0.0025  # [m]
# PhysX separates penetrating bodies at up to this speed. Its default (1e32 m/s) let the
# human hand squeezing the 58 g YCB tennis ball (62 overlapping pieces) fire it away at
# 200 m/s; capped, a 1 mm penetration still resolves within 1 ms. Mesh objects only: the
# primitives keep the simulation they always had.
MESH_MAX_DEPENETRATION_VELOCITY = 1.0  # [m/s]

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
    if obj.is_mesh:
        return build_mesh_object(scene, obj, T_world_object)
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


def cooking_change(vertices: np.ndarray, cooked: np.ndarray) -> float:
    """[m] how far the piece's vertices lie outside the hull PhysX cooked from them
    (0 when it kept them all)."""
    if len(cooked) == len(vertices):
        return 0.0
    from scipy.spatial import ConvexHull

    planes = ConvexHull(np.asarray(cooked, dtype=float)).equations
    return max(0.0, float((vertices @ planes[:, :3].T + planes[:, 3]).max()))


def build_mesh_object(scene: sapien.Scene, obj: ObjectDescription, T_world_object):
    """A mesh object as a dynamic actor made of its convex pieces (the ones the collision
    checker and the planner use: graspframe/model_files/convex.py, object frame), with the mass and
    the inertia of the object set explicitly (the pieces overlap, so PhysX's own mass
    from their volumes would count the overlaps twice)."""
    material = sapien.physx.PhysxMaterial(
        obj.static_friction, obj.dynamic_friction, obj.restitution
    )
    component = sapien.physx.PhysxRigidDynamicComponent()
    for index, piece in enumerate(obj.mesh_geometry().pieces):
        shape = sapien.physx.PhysxCollisionShapeConvexMesh(
            vertices=np.asarray(piece.vertices, dtype=np.float32),
            scale=np.ones(3, dtype=np.float32),
            material=material,
        )
        change = cooking_change(np.asarray(piece.vertices), np.asarray(shape.get_vertices()))
        if change > MAX_COOKING_CHANGE:
            raise GraspframeError(
                f"object {obj.name!r}: PhysX moved convex piece {index} by {1000 * change:.1f} "
                f"mm when cooking it (at most {1000 * MAX_COOKING_CHANGE:.1f} mm accepted); "
                "the simulator would not see the pieces the planner uses"
            )
        component.attach(shape)
    # Principal axes and moments of the inertia about the centroid (the frame origin).
    moments, axes = np.linalg.eigh(obj.inertia)
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    component.max_depenetration_velocity = MESH_MAX_DEPENETRATION_VELOCITY
    component.mass = obj.mass
    component.cmass_local_pose = sapien.Pose(q=quat_wxyz_from_R(axes))
    component.inertia = moments
    component.name = obj.name
    entity = sapien.Entity()
    entity.add_component(component)
    entity.name = obj.name
    entity.pose = to_pose(T_world_object)
    scene.add_entity(entity)
    return entity
