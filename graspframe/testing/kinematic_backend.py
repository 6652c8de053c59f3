"""A kinematic backend: the driver interfaces without a simulator, for testing.

A hardware backend author (or a test of the planner and executor) runs a grasp on it
without SAPIEN. It is deterministic and has no physics: arm joints move towards their
targets at their velocity limits; hand joints follow the core `HandController` (motor
setpoints, controller couplings, breakaway) but a joint does not move a link into the
object, so fingers stop where they touch it. The object stands where it was put; while
at least HOLDING_FINGERS real fingers touch it, it moves rigidly with the palm, and when
they let go it drops back to the height it stood at. It cannot be pushed
(`ObjectProbe.apply_force` is not implemented, as on hardware).

It is not registered as a plugin: build it directly, `KinematicBackend().create_world(config)`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact, PalmSensorReading
from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import PALM
from graspframe.common.transforms import as_pose, inv_T
from graspframe.hal.descriptions import ArmDescription, joints_by_name
from graspframe.hal.drivers import ArmDriver, Backend, HandDriver, ObjectProbe, World, WorldConfig
from graspframe.hal.hand_control import HandController
from graspframe.robot_models.model import model_of
from graspframe.testing.kinematic_geometry import KinematicGeometry

CONTACT_DISTANCE = 1e-3  # [m] a hand shape this close to the object touches it
# No physics, no forces: a touch reports a nominal force that grows with the
# penetration, so the deepest contact is the strongest.
CONTACT_FORCE = 1.0  # [N]
CONTACT_STIFFNESS = 1000.0  # [N/m]
HOLDING_FINGERS = 2  # real fingers (the palm counts) touching the object carry it
BISECTIONS = 8  # halvings of a hand joint's step that would reach into the object


class KinematicArmDriver(ArmDriver):
    """Arm joints that move towards their targets at their velocity limits."""

    def __init__(self, arm: ArmDescription):
        self.arm = arm
        self._q = np.asarray(arm.home_q, dtype=float).copy()
        self._target = self._q.copy()
        self._max_velocity = np.array([j.max_velocity for j in arm.joints])

    @property
    def joint_names(self) -> tuple[str, ...]:
        return self.arm.joint_names

    def set_joint_targets(
        self,
        q: Sequence[float] | NDArray[np.float64],
        qd: Sequence[float] | NDArray[np.float64] | None = None,
    ) -> None:
        q_target = np.asarray(q, dtype=float)
        if q_target.shape != (self.arm.dof,) or not np.all(np.isfinite(q_target)):
            raise GraspframeError(
                f"arm targets must be {self.arm.dof} finite values, got {q_target.tolist()}"
            )
        self._target = q_target.copy()

    def joint_positions(self) -> NDArray[np.float64]:
        return self._q.copy()

    def advance(self, dt: float) -> None:
        """Move every joint towards its target for `dt` [s]."""
        step = self._max_velocity * dt
        self._q = self._q + np.clip(self._target - self._q, -step, step)


class KinematicHandDriver(HandDriver):
    """Hand joints driven by the `HandController`, stopped by the object."""

    def __init__(self, geometry: KinematicGeometry, arm: KinematicArmDriver | None):
        self.hand = geometry.hand
        self._geometry = geometry
        self._arm = arm
        self._controller = HandController(self.hand)
        self._q = {j.name: min(max(0.0, j.lower), j.upper) for j in self.hand.joints}
        self._qd = dict.fromkeys(self._q, 0.0)
        self._controller.reset(self._q)
        self._moved_by = {name: geometry.shapes_moved_by(name) for name in self._q}
        self.place()

    @property
    def joint_names(self) -> tuple[str, ...]:
        return self.hand.joint_names

    def set_joint_targets(self, q_by_joint: Mapping[str, float]) -> None:
        self._controller.command(q_by_joint)

    def joint_positions(self) -> dict[str, float]:
        return dict(self._q)

    @property
    def held_leaders(self) -> dict[str, float]:
        """Leader joints held by a breakaway, with the angle held [rad]."""
        return self._controller.held_leaders

    def place(self, q_hand: Mapping[str, float] | None = None) -> None:
        """Place the model at the arm's joints and these hand joints (default: the
        current ones) [rad]."""
        q_hand = self._q if q_hand is None else q_hand
        arm = self._arm
        if arm is None:
            self._geometry.place(joints_by_name((), None, q_hand))
        else:
            self._geometry.place(joints_by_name(arm.joint_names, arm.joint_positions(), q_hand))

    def advance(self, dt: float) -> None:
        """Move the joints towards the controller's targets for `dt` [s], one joint at a
        time; a joint stops short of pushing a link it moves into the object."""
        targets = self._controller.update(dt, self._q, self._qd)
        q_new = dict(self._q)
        for name, target in targets.items():
            step = self.hand.joint(name).max_velocity * dt
            q_new[name] = self._admissible(
                name, q_new, q_new[name] + np.clip(target - q_new[name], -step, step)
            )
        self._qd = {name: (q_new[name] - self._q[name]) / dt for name in q_new}
        self._q = q_new
        self.place()

    def _admissible(self, name: str, q: dict[str, float], q_try: float) -> float:
        """The joint's value [rad] nearest q_try on the way from q[name] that does not
        move its links deeper into the object."""
        shapes, q_start = self._moved_by[name], q[name]
        if q_try == q_start or not shapes or not self._geometry.object_shapes:
            return float(q_try)
        self.place(q)
        before = self._geometry.min_distance(shapes)

        def allowed(value: float) -> bool:
            self.place({**q, name: value})
            after = self._geometry.min_distance(shapes)
            return after >= 0.0 or after >= before

        if allowed(q_try):
            return float(q_try)
        if before < CONTACT_DISTANCE:
            return q_start  # already touching: the object stops the joint
        low, high = 0.0, 1.0  # fractions of the step: allowed, not allowed
        for _ in range(BISECTIONS):
            middle = (low + high) / 2
            if allowed(q_start + middle * (q_try - q_start)):
                low = middle
            else:
                high = middle
        return float(q_start + low * (q_try - q_start))

    def contacts(self) -> list[Contact]:
        finger_of_link = self.hand.finger_of_link()
        contacts = []
        for d in self._geometry.distances():
            if d.distance < CONTACT_DISTANCE:
                force = CONTACT_FORCE + CONTACT_STIFFNESS * max(0.0, -d.distance)
                contacts.append(
                    Contact(
                        d.link, finger_of_link[d.link], d.p_world, d.n_world, -force * d.n_world
                    )
                )
        return contacts

    def palm_sensor(self) -> PalmSensorReading:
        """The contacts now (a kinematic touch lasts until the hand moves away)."""
        contacts = self.contacts()
        strongest = max(contacts, key=lambda c: np.linalg.norm(c.f), default=None)
        on_palm = any(c.real_finger == PALM for c in contacts)
        return PalmSensorReading(touched=bool(contacts), on_palm=on_palm, first_contact=strongest)

    def T_world_palm(self) -> NDArray[np.float64]:
        return self._geometry.T_world_frame(self.hand.palm_frame)

    def set_free_pose(self, T_world_palm: NDArray[np.float64]) -> None:
        if self._arm is not None:
            super().set_free_pose(T_world_palm)
        T_root_palm = self._geometry.model.T_root_frame(self.hand.palm_frame)
        self._geometry.T_world_root = as_pose(T_world_palm) @ inv_T(T_root_palm)


class KinematicObjectProbe(ObjectProbe):
    """The object's pose in the kinematic world."""

    def __init__(self, geometry: KinematicGeometry):
        self._geometry = geometry
        self.resting_height = float(geometry.T_world_object[2, 3])  # [m] its centroid's z

    def T_world_object(self) -> NDArray[np.float64]:
        return self._geometry.T_world_object.copy()

    def carry(self, T_world_palm_before, T_world_palm_after, held: bool) -> None:
        """Move the object with the palm when held; else let it drop to where it stood."""
        geometry = self._geometry
        if held:
            T_after_before = T_world_palm_after @ inv_T(T_world_palm_before)
            geometry.T_world_object = T_after_before @ geometry.T_world_object
        elif geometry.T_world_object[2, 3] > self.resting_height:
            geometry.T_world_object = geometry.T_world_object.copy()
            geometry.T_world_object[2, 3] = self.resting_height


class KinematicWorld(World):
    """Arm (or floating hand), hand and object moved kinematically, `timestep` per step."""

    arm: KinematicArmDriver | None
    hand: KinematicHandDriver
    object: KinematicObjectProbe | None

    def __init__(self, config: WorldConfig):
        self.config = config
        self._steps = 0
        model = model_of(config.hand) if config.robot is None else config.robot.model
        self._geometry = KinematicGeometry(model, config.hand, config.object, config.T_world_object)
        self.arm = None
        if config.robot is not None:
            self._geometry.T_world_root = as_pose(config.T_world_arm_base, "T_world_arm_base")
            self.arm = KinematicArmDriver(config.robot.arm)
        self.hand = KinematicHandDriver(self._geometry, self.arm)
        self.object = None if config.object is None else KinematicObjectProbe(self._geometry)

    @property
    def time(self) -> float:
        return self._steps * self.config.timestep

    @property
    def timestep(self) -> float:
        return self.config.timestep

    def step(self, n: int = 1) -> None:
        dt = self.config.timestep
        for _ in range(n):
            T_world_palm_before = self.hand.T_world_palm()
            held = len({c.real_finger for c in self.hand.contacts()}) >= HOLDING_FINGERS
            if self.arm is not None:
                self.arm.advance(dt)
            self.hand.advance(dt)
            if self.object is not None:
                self.object.carry(T_world_palm_before, self.hand.T_world_palm(), held)
            self._steps += 1


class KinematicBackend(Backend):
    """Builds `KinematicWorld`s."""

    name = "kinematic"
    summary = "kinematic test worlds: joints move to their targets, no physics"

    def create_world(self, config: WorldConfig) -> KinematicWorld:
        return KinematicWorld(config)
