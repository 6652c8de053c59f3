"""Arm motion on the SAPIEN backend: straight palm lines that stop at contact, retreat."""

from __future__ import annotations

import math

import numpy as np
import pytest
from graspframe_sapien.backend import SapienBackend

from graspframe.common.transforms import R_from_rpy, make_T, rotation_angle
from graspframe.hal import ObjectDescription, WorldConfig
from graspframe.motion.arm_motion import ArmMotion
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.mounting import mount

REGISTRY = default_registry()
BLOCK = ObjectDescription(
    "heavy_block", "box", {"size_x": 0.04, "size_y": 0.04, "size_z": 0.10}, mass=2.0
)
DOWN = np.array([0.0, 0.0, -1.0])
# Palm +z down, palm +x along world +x.
R_WORLD_PALM_DOWN = R_from_rpy(math.pi, 0.0, 0.0)
STOP_TRAVEL_LIMIT = 0.005  # [m] the acceptance bound on travel after the touch


@pytest.fixture(params=REGISTRY.names("arm"))
def motion(request):
    arm, hand = REGISTRY.get_arm(request.param), REGISTRY.get_hand("barrett")
    T_world_block = make_T(p=[0.5, 0.0, BLOCK.half_height])
    robot = mount(arm, hand)
    world = SapienBackend().create_world(
        WorldConfig(hand=hand, robot=robot, object=BLOCK, T_world_object=T_world_block)
    )
    return ArmMotion(world, robot, np.eye(4))


def test_approach_stops_at_contact_within_5_mm_and_retreats(motion):
    top = BLOCK.dimensions["size_z"]
    motion.move_palm_to(make_T(R_WORLD_PALM_DOWN, [0.5, 0.0, top + 0.05]))
    result = motion.move_palm_linear(DOWN, distance=0.10, speed=0.05)

    assert result.stopped_by_contact
    assert result.first_contact.real_finger == "palm"
    # The contact may push the palm back by a fraction of a millimetre.
    assert -0.001 < result.travel_after_contact < STOP_TRAVEL_LIMIT
    palm_z = result.T_world_palm_end[2, 3]
    assert palm_z == pytest.approx(top, abs=STOP_TRAVEL_LIMIT)  # resting on the block
    # The line kept the palm's orientation (1 deg).
    assert rotation_angle(result.T_world_palm_end, R_WORLD_PALM_DOWN) < math.radians(1)

    back = motion.move_palm_linear(-DOWN, distance=0.04, speed=0.05, stop_on_contact=False)
    assert not back.stopped_by_contact
    # Measured from the palm resting on the block, while the braking setpoint may have
    # gone up to the stop bound deeper: the retreat covers 4 cm less at most that.
    assert back.travel == pytest.approx(0.04, abs=STOP_TRAVEL_LIMIT)
    assert motion.world.hand.contacts() == []


def test_free_line_covers_its_distance_straight(motion):
    start = make_T(R_WORLD_PALM_DOWN, [0.45, -0.1, 0.35])
    motion.move_palm_to(start)
    direction = np.array([0.0, 1.0, 0.0])
    result = motion.move_palm_linear(direction, distance=0.2, speed=0.1)
    assert not result.stopped_by_contact
    assert result.travel == pytest.approx(0.2, abs=0.002)
    end = result.T_world_palm_end[:3, 3]
    np.testing.assert_allclose(end, start[:3, 3] + 0.2 * direction, atol=0.002)
