"""The installed environment has every real component, in versions that work together."""

from __future__ import annotations

import numpy as np


def test_kinematics_stack_imports():
    import pinocchio
    import placo

    assert pinocchio.__version__ == "3.8.0"  # placo 0.10.2 is built against exactly this
    assert hasattr(placo, "RobotWrapper")


def test_sapien_builds_a_physics_only_scene():
    import sapien

    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    builder = scene.create_actor_builder()
    builder.add_box_collision(half_size=[0.05, 0.05, 0.05])
    box = builder.build(name="box")
    box.set_pose(sapien.Pose([0.0, 0.0, 1.0]))
    scene.set_timestep(0.01)
    for _ in range(10):
        scene.step()
    assert box.get_pose().p[2] < 1.0  # it fell: physics runs with no renderer


def test_opencv_has_hog():
    import cv2

    assert int(cv2.__version__.split(".")[0]) == 4
    hog = cv2.HOGDescriptor((64, 64), (16, 16), (8, 8), (8, 8), 9)
    features = hog.compute(np.zeros((64, 64), np.uint8))
    assert features.size == 7 * 7 * 4 * 9


def test_rerun_and_ruckig_import():
    import rerun
    import ruckig

    assert rerun.__version__.startswith("0.41")
    otg = ruckig.Ruckig(1, 0.01)
    assert otg.degrees_of_freedom == 1
