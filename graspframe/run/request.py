"""What a run is asked (`RunRequest`) and everything it needs, looked up and read before
it starts (`RunInputs`, `resolve`): bad input fails before anything runs."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from graspframe.common.defaults import (
    DEFAULT_ARM,
    DEFAULT_BACKEND,
    DEFAULT_CAMERA,
    DEFAULT_CLASSIFIER,
    DISTURBANCE_FRACTION,
    LIFT_HEIGHT,
    MAX_CAMERA_NOISE,
    MOUNT_ARM,
    STRATEGY_METHOD,
    STRATEGY_SERVO,
    TABLE_HEIGHT,
    Mount,
    Strategy,
)
from graspframe.common.errors import InputError
from graspframe.common.grasps import HUMAN_HAND, HumanGrasp
from graspframe.hal.depth_camera import DepthCamera
from graspframe.hal.descriptions import ArmDescription, HandDescription
from graspframe.hal.drivers import Backend
from graspframe.hal.mounted_robot import MountedRobot
from graspframe.hal.objects import ObjectDescription
from graspframe.plugin_system.registry import Registry
from graspframe.robot_models.model import model_of
from graspframe.run.scene import Scene, check_on_table, load_scene
from graspframe.strategy.held_check import HELD_TEST_GRASPFRAME, HeldTest, held_test_named

if TYPE_CHECKING:
    # The human reference's simulation and pictures load after the names are looked up.
    from graspframe.strategy.human_reference import HumanReference

MAX_OBJECT_ERROR = 0.5  # [m] larger injected errors are surely a unit mistake
MAX_LIFT_HEIGHT = 0.3  # [m] a higher lift leaves the arm's comfortable workspace
MAX_DISTURBANCE_FRACTION = 5.0  # of the object's weight


@dataclass(frozen=True)
class RunRequest:
    """What to run.

    grasp: the human grasp stated (skips vision); None: classify `image` (default: the
        bundled demo) with `classifier`, the camera and object poses from `scene`.
    object_error: [m] (dx, dy) added to the object position the robot believes (the
        object itself stays put). human_contacts: a measured-contacts file replacing the
        simulated human reference. record: stream a rerun recording of the run.
    mount: "arm" (the hand on `arm`) or "floating" (the hand alone on a free 6-DOF
        base, as in the method's grasp simulator).
    lift_height [m], disturbance_fraction, held_test_name: the held test
        (strategy/held_check.py's HELD_TESTS: "graspframe", or "benchmark", the field's
        convention, gravity off).
    strategy: "method" (the published strategy) or "servo" (its non-volar grasps
        corrected by the depth camera `camera`, its noise model multiplied by
        `camera_noise`).
    """

    hand: str
    grasp: HumanGrasp | None = None
    image: str | None = None
    scene: str | None = None
    classifier: str = DEFAULT_CLASSIFIER
    arm: str = DEFAULT_ARM
    object: str | None = None
    object_error: tuple[float, float] = (0.0, 0.0)
    seed: int = 0
    backend: str = DEFAULT_BACKEND
    out_root: str = "runs"
    human_contacts: str | None = None
    record: bool = True
    mount: Mount = MOUNT_ARM
    lift_height: float = LIFT_HEIGHT
    disturbance_fraction: float = DISTURBANCE_FRACTION
    held_test_name: str = HELD_TEST_GRASPFRAME
    strategy: Strategy = STRATEGY_METHOD
    camera: str = DEFAULT_CAMERA
    camera_noise: float = 1.0

    def __post_init__(self) -> None:
        # A mount or a strategy given by name becomes the enum (a one-line error listing
        # the known ones for an unknown name).
        object.__setattr__(self, "mount", Mount.parse(self.mount))
        object.__setattr__(self, "strategy", Strategy.parse(self.strategy))

    def command(self) -> str:
        """The command line that repeats this run."""
        parts = ["graspframe", "run", "--hand", self.hand]
        if self.grasp is not None:
            parts += ["--grasp", self.grasp.value]
        if self.image:
            parts += ["--image", self.image, "--scene", str(self.scene)]
        parts += ["--arm", self.arm, "--mount", self.mount, "--seed", str(self.seed)]
        if self.object:
            parts += ["--object", self.object]
        if any(self.object_error):
            dx, dy = (1000.0 * v for v in self.object_error)
            parts += ["--object-error-mm", f"{dx:g},{dy:g}"]
        if self.human_contacts:
            parts += ["--human-contacts", self.human_contacts]
        if not self.record:
            parts += ["--no-record"]
        if self.lift_height != LIFT_HEIGHT:
            parts += ["--lift-height-mm", f"{1000.0 * self.lift_height:g}"]
        if self.disturbance_fraction != DISTURBANCE_FRACTION:
            parts += ["--disturbance-fraction", f"{self.disturbance_fraction:g}"]
        if self.held_test_name != HELD_TEST_GRASPFRAME:
            parts += ["--held-test", self.held_test_name]
        if self.strategy != STRATEGY_METHOD:
            parts += ["--strategy", self.strategy]
        if self.camera_noise != 1.0:
            parts += ["--camera-noise", f"{self.camera_noise:g}"]
        return " ".join(parts)

    def held_test(self) -> HeldTest:
        """The held test of this run, for the robot and the human reference alike."""
        if not (0.0 < self.lift_height <= MAX_LIFT_HEIGHT):
            raise InputError(
                f"lift height {1000 * self.lift_height:g} mm is outside (0, "
                f"{1000 * MAX_LIFT_HEIGHT:g}] mm"
            )
        if not (0.0 <= self.disturbance_fraction <= MAX_DISTURBANCE_FRACTION):
            raise InputError(
                f"disturbance fraction {self.disturbance_fraction:g} is outside [0, "
                f"{MAX_DISTURBANCE_FRACTION:g}] (a fraction of the object's weight)"
            )
        return held_test_named(self.held_test_name, self.lift_height, self.disturbance_fraction)


def demo_paths() -> tuple[Path, Path]:
    """The bundled demo image and its scene file."""
    from importlib.resources import files

    folder = Path(str(files("graspframe.run.demo")))
    return folder / "demo.png", folder / "scene.json"


@dataclass(frozen=True)
class RunInputs:
    """Everything a run needs, looked up and read before it starts."""

    hand: HandDescription
    arm: ArmDescription
    backend_cls: type[Backend]
    reference_backend_cls: type[Backend]
    held_test: HeldTest
    obj: ObjectDescription
    human: HandDescription
    reference_file: HumanReference | None
    scene: Scene | None
    image: np.ndarray | None
    camera_cls: type[DepthCamera] | None = None  # the servo strategy's camera
    camera_noise: float = 1.0  # multiplies the simulated camera's noise model
    # The hand on the arm, bolted straight on (None) and through each of its mountings,
    # mounted and checked here, and planned with (empty for the floating mount).
    robots: Mapping[str | None, MountedRobot] = field(default_factory=dict)


def resolve(request: RunRequest, registry: Registry) -> RunInputs:
    """Look every name up and read every input first: bad input fails before anything
    runs."""
    hand = registry.get_hand(request.hand)
    arm = registry.get_arm(request.arm)
    backend_cls = registry.get_backend(request.backend)
    scene = image = None
    if request.grasp is None:
        from graspframe.vision.images import read_image

        if request.image and not request.scene:
            raise InputError("--image needs --scene (the camera and object poses of the image)")
        demo_image, demo_scene = demo_paths()
        registry.get_classifier(request.classifier)
        image = read_image(Path(request.image or demo_image))
        scene = load_scene(request.scene or demo_scene)
    if request.object:
        obj = registry.get_object(request.object)
    elif scene is not None:
        obj = registry.get_object(scene.object_name)
    else:
        assert request.grasp is not None  # without a grasp the scene names the object
        obj = registry.default_object_for(request.grasp)
    if scene is not None:
        check_on_table(scene, obj.half_height, TABLE_HEIGHT)
    if any(not np.isfinite(v) or abs(v) > MAX_OBJECT_ERROR for v in request.object_error):
        raise InputError(
            f"object error {request.object_error} m is not finite or above {MAX_OBJECT_ERROR} m"
        )
    camera_cls = None
    if request.strategy == STRATEGY_SERVO:
        camera_cls = registry.get_camera(request.camera)
    if not (np.isfinite(request.camera_noise) and 0.0 <= request.camera_noise <= MAX_CAMERA_NOISE):
        raise InputError(
            f"camera noise {request.camera_noise:g} is outside [0, {MAX_CAMERA_NOISE:g}] "
            "(a multiple of the camera's noise model)"
        )
    reference_file = None
    if request.human_contacts:
        from graspframe.strategy.human_reference import load_reference_file

        reference_file = load_reference_file(request.human_contacts)
    human = registry.get_hand(HUMAN_HAND)
    reference_backend_cls = registry.get_backend(DEFAULT_BACKEND)
    # Once every name is known, the models load here (once per process: planning and the
    # world reuse them), so that a broken model file fails before anything runs.
    robots = {}
    if request.mount == MOUNT_ARM:
        from graspframe.robot_models.mounting import check_mounts

        robots = check_mounts(arm, hand)  # a hand whose links overlap the arm's fails here
    else:
        model_of(hand)
    return RunInputs(
        hand,
        arm,
        backend_cls,
        reference_backend_cls,
        request.held_test(),
        obj,
        human,
        reference_file,
        scene,
        image,
        camera_cls,
        request.camera_noise,
        robots,
    )
