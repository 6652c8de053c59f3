"""Tests of the parallel gripper plugin: the contract, the preshape distances, SAPIEN.

pip install -e ".[test]" && pytest
"""

from __future__ import annotations

import numpy as np
import pytest
from graspframe_parallel_gripper.description import FINGERTIP_FRAMES, PARALLEL_GRIPPER

from graspframe.hal.drivers import WorldConfig
from graspframe.registry import default_registry
from graspframe.robot_model import CollisionModel
from graspframe.testing import (
    assert_hand_closes,
    assert_hand_contract,
    assert_hand_free_of_self_collision,
    assert_hand_holds_design_objects,
)
from graspframe.transforms import inv_T, make_T

HAND = PARALLEL_GRIPPER


def test_the_hand_honours_the_graspframe_contract():
    # Joints and limits against the URDF, palm frame direction, preshapes within limits,
    # real fingers, the mapping table for all six human grasps, ...
    assert_hand_contract(HAND)


def test_the_installed_plugin_registers_the_hand():
    registry = default_registry()
    assert not [p.name for p in registry.failures]
    assert registry.get_hand("parallel_gripper") is HAND


def test_the_open_preshapes_are_free_of_self_collision():
    assert_hand_free_of_self_collision(HAND)


@pytest.mark.parametrize("name", sorted(HAND.preshapes))
def test_only_the_jaws_meet_when_closed_on_nothing(name):
    # The jaws slide 2 mm above the palm pad: closed on nothing, their inner faces meet
    # (by design) and nothing else touches.
    model = CollisionModel(HAND.urdf())
    model.place(dict(HAND.preshape(name).closed_q))
    assert model.colliding_links() == [("pg_left_jaw", "pg_right_jaw")]


def fingertip_height(q_by_joint: dict[str, float]) -> float:
    """[m] the highest fingertip above the palm surface, along the palm normal (FK)."""
    model = CollisionModel(HAND.urdf())
    model.place(dict(q_by_joint))
    T_palm_root = inv_T(model.T_root_frame(HAND.palm_frame))
    return max((T_palm_root @ model.T_root_frame(tip))[2, 3] for tip in FINGERTIP_FRAMES.values())


@pytest.mark.parametrize("name", sorted(HAND.preshapes))
def test_preshape_delta_matches_forward_kinematics(name):
    preshape = HAND.preshape(name)
    assert preshape.delta == pytest.approx(fingertip_height(preshape.open_q), abs=1e-4)


def test_the_jaws_close_in_sapien():
    backend = default_registry().get_backend("sapien")()
    # A free-floating gripper (no arm, no object), palm high above the table.
    config = WorldConfig(hand=HAND, object=None)
    with backend.create_world(config) as world:
        world.hand.set_free_pose(make_T(p=[0.0, 0.0, 0.5]))
        pinch = HAND.preshape("pinch")
        world.hand.set_joint_targets(pinch.closed_q)
        world.step(round(1.0 / world.timestep))  # 1 s: the jaws move at 0.1 m/s
        reached = world.hand.joint_positions()
        for joint, target in pinch.closed_q.items():
            assert reached[joint] == pytest.approx(target, abs=2e-3), joint
        palm = world.hand.T_world_palm()[:3, 3]
        assert np.allclose(palm, [0.0, 0.0, 0.5], atol=1e-3)


def test_closing_brings_the_jaws_together():
    assert_hand_closes(HAND)


def test_the_gripper_alone_holds_its_design_objects():
    backend = default_registry().get_backend("sapien")()
    assert_hand_holds_design_objects(HAND, backend)
