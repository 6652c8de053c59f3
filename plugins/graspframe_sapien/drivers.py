"""Arm, hand and object handles on a SAPIEN articulation (the driver interfaces)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import sapien
from numpy.typing import NDArray

from graspframe.common.contacts import Contact, PalmSensorReading
from graspframe.common.errors import GraspframeError, UnknownNameError
from graspframe.common.grasps import PALM
from graspframe.common.transforms import inv_T
from graspframe.hal.descriptions import DriveGains, HandDescription
from graspframe.hal.drivers import ArmDriver, HandDriver, ObjectProbe
from graspframe.hal.hand_control import HandController, holding_drive
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe_sapien.articulation import active_joints
from graspframe_sapien.contacts import read_contacts
from graspframe_sapien.poses import to_pose, to_T


class _JointAccess:
    """Positions, velocities and drive targets of named joints of one articulation."""

    def __init__(self, articulation, names: Sequence[str]):
        self.articulation = articulation
        joints = active_joints(articulation)
        order = list(joints)
        missing = [n for n in names if n not in joints]
        if missing:
            raise UnknownNameError("articulation joint", missing[0], order)
        self.names = tuple(names)
        self.joints = [joints[n] for n in names]
        self.index = np.array([order.index(n) for n in names], dtype=int)

    def positions(self) -> NDArray[np.float64]:
        return np.asarray(self.articulation.get_qpos(), dtype=float)[self.index]

    def velocities(self) -> NDArray[np.float64]:
        return np.asarray(self.articulation.get_qvel(), dtype=float)[self.index]


class SapienArmDriver(ArmDriver):
    def __init__(self, articulation, joint_names: Sequence[str]):
        self._access = _JointAccess(articulation, joint_names)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return self._access.names

    def set_joint_targets(self, q, qd=None) -> None:
        q = np.asarray(q, dtype=float)
        if q.shape != (len(self.joint_names),) or not np.all(np.isfinite(q)):
            raise GraspframeError(
                f"arm targets must be {len(self.joint_names)} finite values, got {q.tolist()}"
            )
        qd = np.zeros_like(q) if qd is None else np.asarray(qd, dtype=float)
        for joint, target, velocity in zip(self._access.joints, q, qd, strict=True):
            joint.set_drive_target(float(target))
            joint.set_drive_velocity_target(float(velocity))

    def joint_positions(self) -> NDArray[np.float64]:
        return self._access.positions()


LATCH_WINDOW = 50  # [steps] the palm sensor latches this long after a reading (0.1 s)


class SapienHandDriver(HandDriver):
    """Hand joints driven by the core `HandController` (setpoints, couplings with
    breakaway), contacts and the palm sensor.

    The palm sensor latches: a touch in any physics step since the last reading is
    reported (a brief knock on a light object lasts less than a control cycle). Reading
    contacts every step costs about a third of a run, so the latch watches only while
    the sensor is being polled (for LATCH_WINDOW steps after each reading).
    """

    def __init__(
        self,
        scene,
        articulation,
        hand: HandDescription,
        object_entity,
        free_floating: bool,
    ):
        self.hand = hand
        self.free_floating = free_floating
        self._scene = scene
        self._articulation = articulation
        self._object_entity = object_entity
        self._access = _JointAccess(articulation, hand.joint_names)
        self._followers = _JointAccess(
            articulation, [c.follower for c in hand.couplings if c.in_model]
        )
        self._joint_by_name = dict(zip(self._access.names, self._access.joints, strict=True))
        self._controller = HandController(hand)
        self._holding: set[str] = set()  # joints whose drive is the worm gear's hold
        self._finger_of_link = hand.finger_of_link()
        links = {link.name: link for link in articulation.get_links()}
        self._palm_link = links[hand.palm_frame]
        # From the model, not the simulator: link poses are only valid after a step.
        self._T_root_palm = CollisionModel(model_of(hand)).T_root_frame(hand.palm_frame)
        # Contacts of the first touching step since the last palm sensor reading, and
        # whether any step since then touched a palm link.
        self._first_touch: list[Contact] = []
        self._palm_touched_since_read = False
        self._latch_steps_left = 0

    @property
    def joint_names(self) -> tuple[str, ...]:
        return self._access.names

    def set_joint_targets(self, q_by_joint: Mapping[str, float]) -> None:
        """Command joints [rad] (see `HandController.command`)."""
        self._controller.command(q_by_joint)
        self.update()

    def update(self) -> None:
        """Advance the controller and send its targets to the drives; called before
        every physics step."""
        q = dict(zip(self._access.names, self._access.positions(), strict=True))
        qd = dict(zip(self._access.names, self._access.velocities(), strict=True))
        targets = self._controller.update(self._scene.get_timestep(), q, qd)
        self._sync_holds()
        for name, target in targets.items():
            self._joint_by_name[name].set_drive_target(target)

    def _sync_holds(self) -> None:
        """Give the joints held by a breakaway the hold drive, the others their own."""
        held = set(self._controller.held_leaders)
        for name in held - self._holding:
            self._set_drive(name, holding_drive(self.hand.drive))
        for name in self._holding - held:
            self._set_drive(name, self.hand.drive)
        self._holding = held

    def _set_drive(self, joint_name: str, drive: DriveGains) -> None:
        self._joint_by_name[joint_name].set_drive_property(
            drive.stiffness, drive.damping, drive.force_limit
        )

    def reset_setpoints(self) -> None:
        """Make the measured positions the current setpoints and commands (after a teleport)."""
        self._controller.reset(self.joint_positions())
        self._sync_holds()

    @property
    def held_leaders(self) -> dict[str, float]:
        """Leader joints currently held by a breakaway, with the angle held [rad]."""
        return self._controller.held_leaders

    def joint_positions(self) -> dict[str, float]:
        return dict(zip(self._access.names, map(float, self._access.positions()), strict=True))

    def follower_positions(self) -> dict[str, float]:
        names, positions = self._followers.names, self._followers.positions()
        return dict(zip(names, map(float, positions), strict=True))

    def contacts(self) -> list[Contact]:
        if self._object_entity is None:
            return []
        return read_contacts(
            self._scene, self._object_entity, self._finger_of_link, self._scene.get_timestep()
        )

    def after_step(self) -> None:
        """Latch the touches of the physics step just taken for the palm sensor."""
        if self._latch_steps_left <= 0:
            return
        self._latch_steps_left -= 1
        contacts = self.contacts()
        if contacts and not self._first_touch:
            self._first_touch = contacts
        # Any palm link counts (the sensor pad, and the palm body around it).
        self._palm_touched_since_read |= any(c.real_finger == PALM for c in contacts)

    def palm_sensor(self) -> PalmSensorReading:
        """Touches since the last reading (or now, when nothing touched since)."""
        contacts = self._first_touch or self.contacts()
        on_palm = self._palm_touched_since_read or any(c.real_finger == PALM for c in contacts)
        self._first_touch, self._palm_touched_since_read = [], False
        self._latch_steps_left = LATCH_WINDOW
        strongest = max(contacts, key=lambda c: np.linalg.norm(c.f), default=None)
        return PalmSensorReading(touched=bool(contacts), on_palm=on_palm, first_contact=strongest)

    def T_world_palm(self) -> NDArray[np.float64]:
        return to_T(self._palm_link.entity_pose)

    def set_free_pose(self, T_world_palm: NDArray[np.float64]) -> None:
        """Place a free-floating hand (teleport; do it before the hand touches anything)."""
        if not self.free_floating:
            super().set_free_pose(T_world_palm)
        self._articulation.set_root_pose(to_pose(T_world_palm @ inv_T(self._T_root_palm)))


class SapienObjectProbe(ObjectProbe):
    """The object actor's pose, and a force on its centroid re-applied before every step
    (PhysX clears applied forces after each step)."""

    def __init__(self, actor):
        self._actor = actor
        self._body = actor.find_component_by_type(sapien.physx.PhysxRigidDynamicComponent)
        self._force: NDArray[np.float64] | None = None

    def T_world_object(self) -> NDArray[np.float64]:
        return to_T(self._actor.get_pose())

    def apply_force(self, f_world: NDArray[np.float64] | None) -> None:
        if f_world is None:
            self._force = None
            return
        f_world = np.asarray(f_world, dtype=float)
        if f_world.shape != (3,) or not np.all(np.isfinite(f_world)):
            raise GraspframeError(f"object force must be 3 finite numbers [N], got {f_world}")
        self._force = f_world

    def before_step(self) -> None:
        """Apply the standing force for the next physics step."""
        if self._force is not None:
            self._body.add_force_torque(self._force.astype(np.float32), np.zeros(3, np.float32))
