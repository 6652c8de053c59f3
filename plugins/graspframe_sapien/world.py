"""The SAPIEN backend's world: physics only, with a table, the object and the robot
(the registered class, `SapienBackend`, is in backend.py)."""

from __future__ import annotations

import numpy as np

from graspframe.common.transforms import as_pose
from graspframe.hal.drivers import World, WorldConfig
from graspframe.robot_models.model import model_of
from graspframe_sapien.articulation import (
    configure_drives,
    create_scene,
    load_articulation,
    set_qpos_by_name,
)

# Also importable from here, where plugin test suites written for earlier versions find it.
from graspframe_sapien.backend import SapienBackend as SapienBackend
from graspframe_sapien.drivers import SapienArmDriver, SapienHandDriver, SapienObjectProbe
from graspframe_sapien.poses import to_pose
from graspframe_sapien.scene_objects import build_object, build_table


class SapienWorld(World):
    """Table + object + hand (on an arm, or free-floating), stepped at a fixed timestep.

    The robot's links ignore gravity: its joints are position-controlled, as a real arm
    and hand compensate gravity, so the PD drives only have to track.
    """

    hand: SapienHandDriver
    object: SapienObjectProbe | None

    def __init__(self, config: WorldConfig):
        self.config = config
        self._scene = create_scene(config.timestep)
        self._steps = 0

        T_world_object = as_pose(config.T_world_object, "T_world_object")
        build_table(self._scene, T_world_object[:2, 3], config.table_height)
        self._object_actor = None
        if config.object is not None:
            self._object_actor = build_object(self._scene, config.object, T_world_object)
        self.object = SapienObjectProbe(self._object_actor) if self._object_actor else None

        hand, arm = config.hand, config.arm
        model = model_of(hand) if config.robot is None else config.robot.model
        self.articulation = load_articulation(self._scene, model, fix_root=True)
        for link in self.articulation.get_links():
            link.disable_gravity = True

        followers = model.mimic_followers
        gains = {name: hand.drive for name in hand.joint_names}
        if arm is not None:
            gains |= {name: arm.drive for name in arm.joint_names}
        configure_drives(self.articulation, gains, followers)

        if arm is not None:
            self.articulation.set_root_pose(to_pose(as_pose(config.T_world_arm_base)))
            set_qpos_by_name(self.articulation, dict(zip(arm.joint_names, arm.home_q, strict=True)))
            self.arm = SapienArmDriver(self.articulation, arm.joint_names)
            self.arm.set_joint_targets(np.asarray(arm.home_q))
        else:
            self.arm = None
        self.hand = SapienHandDriver(
            self._scene,
            self.articulation,
            hand,
            self._object_actor,
            free_floating=arm is None,
        )

    def teleport_hand(self, q_by_joint: dict[str, float]) -> None:
        """Set hand joints [rad] instantly (simulation only: tests, initial postures);
        <mimic> followers are set from their leaders, setpoints reset to the new pose."""
        set_qpos_by_name(self.articulation, self.config.hand.with_model_followers(q_by_joint))
        self.hand.reset_setpoints()
        self.hand.set_joint_targets(q_by_joint)

    @property
    def scene(self):
        """The SAPIEN scene (for backend-specific tools; core code never uses it)."""
        return self._scene

    @property
    def time(self) -> float:
        return self._steps * self.config.timestep

    @property
    def timestep(self) -> float:
        return self.config.timestep

    def step(self, n: int = 1) -> None:
        for _ in range(n):
            self.hand.update()
            if self.object is not None:
                self.object.before_step()
            self._scene.step()
            self.hand.after_step()
            self._steps += 1
