"""Loading a robot model into a SAPIEN physics-only scene and driving its joints.

SAPIEN's renderer needs a GPU, so scenes hold only a PhysX CPU system, and the model
(`UrdfModel`: the URDF text in memory, visuals taken out, collision meshes as convex
pieces) is given to SAPIEN's URDF parser as text. <mimic> joints are enforced by fixed
tendons built here (SAPIEN's own loader inverts the relation of two joints on one link),
with each follower set where its leader puts it before the first step; followers must
have no drive of their own, or the drive fights the coupling.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sapien

from graspframe.common.errors import DescriptionError
from graspframe.hal.descriptions import DriveGains
from graspframe.model_files.urdf_model import UrdfModel

# Collision group bit that, with the same g3 id, stops a robot's links colliding with
# each other: shapes A and B collide iff ((A.g0 & B.g1) or (A.g1 & B.g0)) and not
# ((A.g2 & B.g2) and A.g3 == B.g3). Self-collision adds nothing to grasping here and
# overlapping link shapes at joints would otherwise jitter.
NO_SELF_COLLISION_BIT = 1 << 30


def create_scene(timestep: float) -> sapien.Scene:
    """A physics-only scene (no renderer) with the given step [s]."""
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(timestep)
    return scene


def load_articulation(
    scene: sapien.Scene, model: UrdfModel, fix_root: bool, robot_id: int = 1
) -> sapien.physx.PhysxArticulation:
    """Load a robot model as one articulation without self-collision, its <mimic>
    couplings held from the first step."""
    loader = scene.create_urdf_loader()
    loader.fix_root_link = fix_root
    # What `loader.parse` sets before parsing a file: no package folder (the model names
    # its meshes by absolute path), the folder of the source file, no SRDF pairs.
    loader.package_dir = None
    loader.urdf_dir = str(model.sources[0].parent) if model.sources else "."
    loader.ignore_pairs = []
    try:
        builders, actor_builders, _ = loader._parse_urdf(model.text)
        if len(builders) != 1 or actor_builders:
            raise DescriptionError(f"the model holds {len(builders)} articulations, not one")
        articulation = _build_with_couplings(builders[0], fix_root)
    except DescriptionError:
        raise
    except Exception as exc:
        raise DescriptionError(f"SAPIEN cannot load {model.describe()}: {exc}") from exc
    if articulation is None:
        raise DescriptionError(f"SAPIEN loaded no articulation from {model.describe()}")
    _satisfy_couplings(articulation, model.mimic_followers)
    for link in articulation.get_links():
        for shape in link.get_collision_shapes():
            g0, g1, g2, _ = shape.get_collision_groups()
            shape.set_collision_groups([g0, g1, g2 | NO_SELF_COLLISION_BIT, robot_id])
    return articulation


def _build_with_couplings(builder, fix_root: bool) -> sapien.physx.PhysxArticulation:
    """The articulation of a URDF builder, each <mimic> follower coupled to its leader by
    a fixed tendon: q_follower = multiplier * q_leader + offset (the URDF's relation).

    SAPIEN's own `build` orders the tendon's links by topology and gets the relation
    inverted for two joints that hang from the same link (q_leader = multiplier *
    q_follower + offset: invisible at multiplier 1 and offset 0, wrong otherwise); here
    the leader's link comes before the follower's in both cases."""
    links = builder.build_entities(fix_root_link=fix_root)
    component = sapien.physx.PhysxArticulationLinkComponent
    articulation = links[0].find_component_by_type(component).articulation
    for record in builder.mimic_joint_records:
        follower = articulation.find_joint_by_name(record.joint)
        leader = articulation.find_joint_by_name(record.mimic)
        if follower.parent_link == leader.child_link:  # a chain: leader, then follower
            root = leader.parent_link
        elif follower.parent_link == leader.parent_link:  # siblings
            root = follower.parent_link
        else:
            raise DescriptionError(
                f"<mimic> joint {record.joint!r} follows {record.mimic!r}, which is neither "
                "its parent joint nor a joint on the same link: not simulated"
            )
        if root is None:
            raise DescriptionError(
                f"<mimic> joint {record.joint!r} follows the root joint {record.mimic!r}: "
                "a coupling needs a link above its leader"
            )
        m = record.multiplier
        articulation.create_fixed_tendon(
            [root, leader.child_link, follower.child_link],
            [0, -m, 1],
            [0, -1 / m, 1],
            rest_length=record.offset,
            stiffness=1e5,
        )
    for link in links:
        builder.scene.add_entity(link)
    return articulation


def active_joints(articulation) -> dict[str, sapien.physx.PhysxArticulationJoint]:
    """Active joint name -> joint, in articulation order."""
    return {joint.name: joint for joint in articulation.get_active_joints()}


def configure_drives(
    articulation,
    gains_by_joint: Mapping[str, DriveGains],
    followers: Mapping[str, tuple[str, float, float]],
) -> None:
    """PD drives and armatures on the named joints; mimic followers (follower -> (leader,
    multiplier, offset)) get no drive (the coupling moves them) but their leader's
    armature."""
    joints = active_joints(articulation)
    for name, gains in gains_by_joint.items():
        if name not in joints:
            raise DescriptionError(f"joint {name!r} is not an active joint of the articulation")
        if name in followers:
            continue
        joints[name].set_drive_property(gains.stiffness, gains.damping, gains.force_limit)
        joints[name].set_armature([gains.armature])
    for follower, (leader, _multiplier, _offset) in followers.items():
        if follower in joints and leader in gains_by_joint:
            joints[follower].set_armature([gains_by_joint[leader].armature])


def _satisfy_couplings(articulation, followers: Mapping[str, tuple[str, float, float]]) -> None:
    """Set each <mimic> follower where its leader's position puts it. A model loads with
    every joint at 0, which breaks a coupling with an offset (the Ability hand's distal
    joints: 0.72 rad at a leader's 0); PhysX's coupling then corrects the whole error in
    one step and the articulation blows up (NaN poses)."""
    names = list(active_joints(articulation))
    qpos = np.array(articulation.get_qpos(), dtype=float)
    for follower, (leader, multiplier, offset) in followers.items():
        if follower in names and leader in names:
            qpos[names.index(follower)] = multiplier * qpos[names.index(leader)] + offset
    articulation.set_qpos(qpos)


def set_qpos_by_name(articulation, q_by_joint: Mapping[str, float]) -> None:
    """Teleport joints to positions [rad] (followers of <mimic> included by the caller)."""
    names = list(active_joints(articulation))
    qpos = np.array(articulation.get_qpos(), dtype=float)
    for name, value in q_by_joint.items():
        qpos[names.index(name)] = value
    articulation.set_qpos(qpos)
