"""The servo strategy: the method's strategy (method.py) with the object's position
measured by a depth camera and the hand moved by the correction before it closes.

For the grasps the method leaves without feedback (the non-volar ones): before the arm
moves, the camera's image (the robot filtered out) is fitted with the object's model
(perception/localise.py); when the fit is accepted and the object is more than
`tolerance` from where the robot believes it, the whole path (via, descent, approach) is
shifted by the difference; this repeats until the estimate moves less than the tolerance
or `max_steps` is reached. The loop runs again at the via (the rest of the path shifted,
the hand moved to the new via), at the pre-approach pose (the approach shifted, the hand
moved to its new start) and at the standoff, with the hand partly in front of the object,
with short sideways moves. Each step is an `execute.servo` event (the estimated position,
the fit's quality, the correction). The volar grasps keep the method's palm-sensor loop
as it is.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from graspframe.common.camera import Camera
from graspframe.hal.depth_camera import CameraMount, DepthCamera, DepthImage
from graspframe.hal.descriptions import HandDescription, joints_by_name
from graspframe.hal.drivers import World, WorldConfig
from graspframe.hal.objects import ObjectDescription
from graspframe.motion.arm_motion import ArmMotion
from graspframe.perception.localise import ObjectFit, ObjectModel, fit_object
from graspframe.perception.self_filter import RobotSelfFilter
from graspframe.perception.servo_step import ServoStep
from graspframe.pictures.render3d import look_at
from graspframe.plugin_system import events
from graspframe.strategy.execution import ExecutionLog, Grip
from graspframe.strategy.method import ExecutorParams, _Strategy
from graspframe.strategy.planner import GraspPlan
from graspframe.strategy.segments import approach_line, moved_pose, sideways_line

STANDOFF_SKIPPED = "larger than the standoff allows"  # a step's `skipped` then
# The head camera: 320 x 240 px at 290 px focal length (the QVGA mode of the Kinect class,
# 580 px at 640 x 480), in the world above and beside the arm's base (at the world origin
# on the arm mount; the hand alone works in the same scene), looking at the believed
# object.
HEAD_CAMERA = Camera(320, 240, 290.0, 290.0, 160.0, 120.0)
P_WORLD_HEAD = (0.15, -0.45, 0.8)  # [m]


def head_camera(p_world_target: ArrayLike) -> CameraMount:
    """The head camera looking at `p_world_target` [m] (world up: +z)."""
    T_world_camera = look_at(P_WORLD_HEAD, p_world_target, (0.0, 0.0, 1.0))
    return CameraMount(HEAD_CAMERA, T_world_camera=T_world_camera)


@dataclass(frozen=True)
class ServoParams:
    """The servo loop's settings, each written here only."""

    tolerance: float = 0.003  # [m] an estimate this close to the belief is left alone
    max_steps: int = 4  # looks per stage (start, via, pre-approach, standoff)
    max_standoff_shift: float = 0.02  # [m] a larger correction at the standoff is not made


@dataclass(frozen=True)
class ServoStrategy:
    """The servo strategy for one plan: a `GraspPolicy` (execution.py). `camera` is the
    registered depth camera class, built for the world of `config` on first use."""

    plan: GraspPlan
    hand: HandDescription
    obj: ObjectDescription
    config: WorldConfig
    camera: type[DepthCamera]
    mount: CameraMount
    T_world_object_believed: NDArray[np.float64]
    params: ExecutorParams = field(default_factory=ExecutorParams)
    servo: ServoParams = field(default_factory=ServoParams)
    seed: int = 0
    noise_scale: float = 1.0
    # Filled as it runs: each step, and its depth image.
    steps: list[ServoStep] = field(default_factory=list)
    images: list[tuple[DepthImage, ServoStep]] = field(default_factory=list)

    def grasp(self, world: World, motion: ArmMotion, log: ExecutionLog) -> Grip:
        return _ServoStrategy(
            self.plan, world, motion, self.hand, self.obj, self.params, log, self
        ).run()


@dataclass
class _ServoStrategy(_Strategy):
    owner: ServoStrategy | None = None

    def _start_perception(self) -> None:
        """The camera, the robot's self filter and the object's model (the non-volar
        grasps only: the volar ones keep the method's palm-sensor loop)."""
        owner = self.owner
        assert owner is not None and owner.config.robot is not None
        self.camera = owner.camera(owner.config, owner.mount, owner.seed, owner.noise_scale)
        self.self_filter = RobotSelfFilter(owner.config.robot.model, owner.config.T_world_arm_base)
        self.model = ObjectModel(self.obj, owner.seed)
        self.T_world_object_believed = owner.T_world_object_believed.copy()
        # The palm goal as the looks have shifted it so far (self.path: the segments).
        self.T_goal = self.plan.T_world_palm_goal.copy()

    def run(self) -> Grip:
        if self.plan.volar:
            return super().run()
        self._start_perception()
        preshape = self.hand.preshape(self.plan.preshape)
        self._move_to_pre_approach_servoed(preshape.open_q)
        self._servo("pre-approach", self._shift_approach)
        palm_contact = self._approach_non_volar()
        self._servo("standoff", self._shift_at_standoff)
        self._close(preshape.closed_q)
        self.motion.idle(round(self.p.hold_time / self.world.timestep))
        goal = self.T_goal[:3, 3]
        return Grip(palm_contact, 0, ((float(goal[0]), float(goal[1]), float(goal[2])),))

    # -- the loop -----------------------------------------------------------------------

    def _servo(self, stage: str, move: Callable[[NDArray[np.float64]], bool]) -> None:
        assert self.owner is not None
        for step in range(1, self.owner.servo.max_steps + 1):
            image, fit = self._measure()
            shift = np.array([*fit.shift_xy, 0.0])
            act = fit.accepted and float(np.linalg.norm(shift)) > self.owner.servo.tolerance
            correction_mm = (1000.0 * float(shift[0]), 1000.0 * float(shift[1]))
            record = ServoStep(stage, step, fit, correction_mm if act else (0.0, 0.0))
            if act and not move(shift):
                act = False
                record = replace(record, correction_mm=(0.0, 0.0), skipped=STANDOFF_SKIPPED)
            self.owner.steps.append(record)
            self.owner.images.append((image, record))
            c = image.intrinsics
            self.emit(
                events.EXECUTE_DEPTH_IMAGE,
                stage=stage,
                step=step,
                depth_m=image.depth_m,
                intrinsics={
                    "fx": c.fx,
                    "fy": c.fy,
                    "cx": c.cx,
                    "cy": c.cy,
                    "width": c.width,
                    "height": c.height,
                },
                T_world_camera=image.T_world_camera,
                p_world_fitted=fit.T_world_object[:3, 3],
            )
            self.emit(events.EXECUTE_SERVO, **record.to_json())
            if not act:
                return
            self.T_world_object_believed[:2, 3] += shift[:2]

    def _measure(self) -> tuple[DepthImage, ObjectFit]:
        """The depth image with the robot filtered out, and the object fitted to it."""
        assert self.world.arm is not None and self.owner is not None
        image = self.camera.capture(self.world)
        q = joints_by_name(
            self.owner.config.robot.arm.joint_names,  # type: ignore[union-attr]
            self.world.arm.joint_positions(),
            self.world.hand.joint_positions(),
        )
        q = self.hand.with_model_followers(q)
        cleaned = self.self_filter.without_robot(image, q)
        table = self.owner.config.table_height
        return cleaned, fit_object(cleaned, self.model, self.T_world_object_believed, table)

    # -- the moves ----------------------------------------------------------------------

    def _move_to_pre_approach_servoed(self, open_q: Mapping[str, float]) -> None:
        """The method's move to the pre-approach pose with two looks: before the arm
        moves (its way to the via can sweep through an object 5 cm from the belief) and
        at the via, before the descent."""
        self._servo("start", self._shift_plan)
        self._move_to_pre_approach(open_q, at_via=lambda: self._servo("via", self._shift_via))

    def _shift_plan(self, shift: NDArray[np.float64]) -> bool:
        """Shift the whole path by `shift` [m] before the arm moves."""
        self.T_goal = moved_pose(self.T_goal, shift)
        self.path = self.path.shifted(shift)
        return True

    def _shift_via(self, shift: NDArray[np.float64]) -> bool:
        """Shift the via, and the path after it, by `shift` [m] and go to the new via."""
        self.T_goal = moved_pose(self.T_goal, shift)
        self.path = self.path.shifted(shift)
        self.motion.move_palm_to(self.path.T_world_palm_via)
        return True

    def _shift_approach(self, shift: NDArray[np.float64]) -> bool:
        """Shift the whole approach by `shift` [m] and go to its new start."""
        self.T_goal = moved_pose(self.T_goal, shift)
        planned = self.path.approach
        approach = approach_line(self.plan, self.T_goal, planned.distance, planned.speed)
        self.motion.move_palm_to(approach.T_world_palm_start)
        self.path = replace(self.path, approach=approach)
        return True

    def _shift_at_standoff(self, shift: NDArray[np.float64]) -> bool:
        """Move the palm sideways by `shift` [m] at the standoff, when it is small."""
        assert self.owner is not None
        distance = float(np.linalg.norm(shift))
        if distance > self.owner.servo.max_standoff_shift:
            return False
        self.T_goal = moved_pose(self.T_goal, shift)
        sideways = sideways_line(self.motion.T_world_palm_commanded(), shift, self.p.approach_speed)
        self.motion.follow(sideways, stop_on_contact=False)
        return True
