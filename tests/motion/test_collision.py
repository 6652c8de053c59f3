"""Collision checks of the KUKA + Barrett against the table and a can
(graspframe.motion.collision), on the real models.

Arm configurations come from IK (graspframe.motion.ik) of palm poses chosen so that the
verdict is known in advance; the free home pose is first confirmed by forward kinematics
of every collision shape (graspframe.robot_models.model.CollisionModel), independently of the
checker.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import R_from_rpy, make_T
from graspframe.motion.collision import (
    DEFAULT_MARGIN,
    Collision,
    Obstacle,
    RobotCollisionChecker,
    object_obstacle,
    table_obstacle,
)
from graspframe.motion.ik import IkSolver
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.robot_models.mounting import mount

REGISTRY = default_registry()
ARM = REGISTRY.get_arm("kuka")
HAND = REGISTRY.get_hand("barrett")
CAN = REGISTRY.get_object("large_cylinder")  # radius 0.04 m, length 0.11 m
ROBOT = mount(ARM, HAND)

TABLE_HEIGHT = 0.0  # [m]
OBJECT_XY = (0.55, 0.20)  # [m] the default scene
T_WORLD_CAN = make_T(p=[*OBJECT_XY, TABLE_HEIGHT + CAN.half_height])
HAND_CLOSED_AT_ZERO = {name: 0.0 for name in HAND.joint_names}
HAND_OPEN = dict(HAND.preshape_for(HumanGrasp.LARGE_DIAMETER).open_q)  # wrap, 10 deg flexion
ARM_LINKS = ("kr5_base", *(f"kr5_link_{i}" for i in range(1, 7)))
HAND_LINKS = frozenset(link for links in HAND.real_fingers.values() for link in links)


def pairs(found: list[Collision]) -> list[tuple[str, str]]:
    return [(c.robot_link, c.obstacle) for c in found]


def same_verdicts(got: list[Collision], expected: list[Collision]) -> bool:
    """Same pairs, same distances: penetration depths are EPA estimates (tolerance
    1e-6 m; repeated calls were seen to differ by ~2e-9 m), so near ties may swap."""
    got_by_pair = {(c.robot_link, c.obstacle): c.distance for c in got}
    expected_by_pair = {(c.robot_link, c.obstacle): c.distance for c in expected}
    return got_by_pair.keys() == expected_by_pair.keys() and all(
        math.isclose(d, expected_by_pair[pair], abs_tol=1e-6) for pair, d in got_by_pair.items()
    )


def obstacles() -> list[Obstacle]:
    return [table_obstacle(TABLE_HEIGHT, OBJECT_XY), object_obstacle(CAN, T_WORLD_CAN)]


def q_full(q_arm, q_hand) -> dict[str, float]:
    """Every joint of the combined model by name [rad], <mimic> followers included."""
    return dict(zip(ARM.joint_names, q_arm, strict=True)) | HAND.with_model_followers(q_hand)


@pytest.fixture(scope="module")
def checker() -> RobotCollisionChecker:
    return RobotCollisionChecker(ROBOT.model, np.eye(4), obstacles())


@pytest.fixture(scope="module")
def ik() -> IkSolver:
    return IkSolver(ROBOT)


def _palm_down(ik: IkSolver, p_world, q_hand) -> dict[str, float]:
    """Arm (IK) + hand configuration with the palm origin at p_world [m], palm normal
    pointing down (the home orientation). World = arm base frame here."""
    T_base_palm = ik.forward_palm(ARM.home_q)
    T_base_palm[:3, 3] = p_world
    solution = ik.solve(T_base_palm, q_hand=q_hand)
    return q_full(solution.q_arm, q_hand)


@pytest.fixture(scope="module")
def q_home() -> dict[str, float]:
    return q_full(ARM.home_q, HAND_CLOSED_AT_ZERO)


@pytest.fixture(scope="module")
def q_in_can(ik) -> dict[str, float]:
    """The palm origin at the can's centroid: the palm is inside the can."""
    return _palm_down(ik, T_WORLD_CAN[:3, 3], HAND_CLOSED_AT_ZERO)


@pytest.fixture(scope="module")
def q_on_table(ik) -> dict[str, float]:
    """Palm 1 cm above the table, facing down, fingers open (they reach ~4.5 cm below the
    palm), 25 cm from the can."""
    return _palm_down(ik, [0.45, -0.05, TABLE_HEIGHT + 0.01], HAND_OPEN)


def _lowest_z(shape, T) -> float:
    """[m] lowest world z of a coal box or cylinder at pose T."""
    R = T[:3, :3]
    if type(shape).__name__ == "Box":
        return T[2, 3] - float(np.abs(R[2]) @ shape.halfSide)
    cos = abs(R[2, 2])
    return T[2, 3] - cos * shape.halfLength - shape.radius * math.sqrt(max(0.0, 1 - cos**2))


def _bounding_radius(shape) -> float:
    if type(shape).__name__ == "Box":
        return float(np.linalg.norm(shape.halfSide))
    return math.hypot(shape.radius, shape.halfLength)


def test_home_pose_is_free(checker, q_home):
    # Independent forward kinematics: every shape clears the table top and the can's
    # bounding sphere by more than the margin (the arm base plate stands *on* z = 0 but
    # the table, centred under the can, ends 14 cm before it).
    model = CollisionModel(ROBOT.model)
    model.place(q_home)
    can_radius = math.hypot(CAN.dimensions["radius"], CAN.half_height)
    table_near_edge = OBJECT_XY[0] - 0.30
    for link, shape, T in model.shapes():
        reach = _bounding_radius(shape)
        if T[0, 3] + reach > table_near_edge:
            assert _lowest_z(shape, T) > TABLE_HEIGHT + DEFAULT_MARGIN, link
        gap = np.linalg.norm(T[:3, 3] - T_WORLD_CAN[:3, 3]) - reach - can_radius
        assert gap > DEFAULT_MARGIN, link
    assert checker.collisions(q_home) == []


def test_palm_inside_the_object(checker, q_in_can):
    found = checker.collisions(q_in_can)
    on_can = [c for c in found if c.obstacle == "object"]
    assert {"bh_palm_pad", "bh_base"} <= {c.robot_link for c in on_can}
    assert all(c.robot_link in HAND_LINKS for c in on_can)
    pad = next(c for c in on_can if c.robot_link == "bh_palm_pad")
    # The 3 mm pad lies just below the palm frame at the can's centroid: it is 55 mm
    # deep along the axis (half the can's length), the shortest way out.
    assert pad.distance == pytest.approx(-CAN.half_height, abs=2e-3)
    assert found == sorted(found, key=lambda c: c.distance)


def test_fingers_in_the_table(checker, q_on_table):
    found = checker.collisions(q_on_table)
    assert found, "fingers 3.5 cm into the table top were not reported"
    assert all(c.obstacle == "table" for c in found)
    assert {c.robot_link for c in found} >= {"bh_f1_dist_link", "bh_f2_dist_link"}
    assert all(c.robot_link in HAND_LINKS for c in found)
    worst = found[0]
    assert worst.distance < -0.01
    assert worst.robot_link in worst.describe() and "table" in worst.describe()


def test_links_and_obstacles_restrict_the_check(checker, q_in_can, q_on_table):
    assert checker.collisions(q_in_can, links=ARM_LINKS) == []
    only_pad = checker.collisions(q_in_can, links=["bh_palm_pad"])
    assert [c.robot_link for c in only_pad] == ["bh_palm_pad"]
    assert checker.collisions(q_on_table, obstacles=["object"]) == []
    assert same_verdicts(
        checker.collisions(q_on_table, obstacles=["table"]), checker.collisions(q_on_table)
    )
    assert all(c.obstacle == "table" for c in checker.collisions(q_in_can, obstacles=["table"]))
    # the full check after a restricted one still sees everything
    assert any(c.obstacle == "object" for c in checker.collisions(q_in_can))
    # a link without shapes is accepted and never collides
    assert checker.collisions(q_in_can, links=["bh_palm_frame"]) == []
    with pytest.raises(GraspframeError, match="bh_no_such_link"):
        checker.collisions(q_in_can, links=["bh_no_such_link"])
    with pytest.raises(GraspframeError, match="floor"):
        checker.collisions(q_in_can, obstacles=["floor"])


def test_first_collision_on_path(checker, q_home, q_in_can):
    path = [
        {name: (1 - s) * q_home[name] + s * q_in_can[name] for name in q_home}
        for s in np.linspace(0.0, 1.0, 21)
    ]
    hit = checker.first_collision_on_path(path)
    assert hit is not None
    index, collision = hit
    assert 0 < index < len(path) - 1
    assert all(checker.collisions(q) == [] for q in path[:index])
    at_index = checker.collisions(path[index])
    same_pair = [c for c in at_index if pairs([c]) == pairs([collision])]
    assert same_verdicts([collision], same_pair)
    assert collision.distance == pytest.approx(at_index[0].distance, abs=1e-6)
    assert checker.first_collision_on_path(path[:index]) is None
    assert checker.first_collision_on_path(path, links=ARM_LINKS) is None


def test_verdicts_do_not_depend_on_where_the_world_is(checker, q_home, q_in_can, q_on_table):
    T_new_world = make_T(R_from_rpy(0.3, -0.2, 1.1), [1.5, -0.7, 0.4])
    moved = RobotCollisionChecker(
        ROBOT.model, T_new_world, [o.moved(T_new_world) for o in obstacles()]
    )
    for q in (q_home, q_in_can, q_on_table):
        assert same_verdicts(moved.collisions(q), checker.collisions(q))


def test_table_under_the_arm_base_is_ignored_on_request(q_home):
    # A can at x = 0.30 m puts the table's near edge at x = 0: the base plate (bottom at
    # z = 0) rests on the table top.
    table = [table_obstacle(TABLE_HEIGHT, (0.30, 0.0))]
    found = RobotCollisionChecker(ROBOT.model, None, table).collisions(q_home)
    assert pairs(found) == [("kr5_base", "table")]
    assert found[0].distance == pytest.approx(0.0, abs=1e-6)
    for ignore in ([("kr5_base", "table")], ["kr5_base"]):
        quiet = RobotCollisionChecker(ROBOT.model, None, table, ignore=ignore)
        assert quiet.collisions(q_home) == []


def test_hand_alone_at_a_root_pose():
    # The Barrett URDF alone, root z up: its palm pad (84 mm up the root's z) at the can's
    # centroid, then the hand lifted 20 cm, clear of everything.
    T_world_hand = make_T(p=[*OBJECT_XY, CAN.half_height - 0.084])
    inside = RobotCollisionChecker(model_of(HAND), T_world_hand, obstacles())
    assert "bh_palm_pad" in {c.robot_link for c in inside.collisions({}, obstacles=["object"])}
    T_world_hand[2, 3] += 0.20
    lifted = RobotCollisionChecker(model_of(HAND), T_world_hand, obstacles())
    assert lifted.collisions({}) == []


def test_margin_counts_clearance_not_only_contact():
    # The hand alone, root z up, its base cylinder's bottom face (the root plane) 3 mm
    # above the can's top face, coaxial: a 3 mm gap.
    T_world_hand = make_T(p=[*OBJECT_XY, TABLE_HEIGHT + 2 * CAN.half_height + 0.003])
    close = RobotCollisionChecker(model_of(HAND), T_world_hand, obstacles(), margin=0.005)
    found = close.collisions({})
    assert pairs(found) == [("bh_base", "object")]
    assert found[0].distance == pytest.approx(0.003, abs=1e-6)
    assert "3.0 mm from the object" in found[0].describe()
    loose = RobotCollisionChecker(model_of(HAND), T_world_hand, obstacles(), margin=0.002)
    assert loose.collisions({}) == []


def test_bad_inputs_are_reported(checker):
    with pytest.raises(GraspframeError, match=r"'kr5_a7'.*kr5_a1"):
        checker.collisions({"kr5_a7": 0.0})
    with pytest.raises(GraspframeError, match="distinct"):
        RobotCollisionChecker(ROBOT.model, None, obstacles() * 2)
    with pytest.raises(GraspframeError, match="needs dimensions"):
        Obstacle("table", "box", {"radius": 0.1}, np.eye(4))
    with pytest.raises(GraspframeError, match="margin"):
        RobotCollisionChecker(ROBOT.model, None, obstacles(), margin=-0.001)


def test_describe():
    assert Collision("kr5_link_5", "table", -0.012).describe() == (
        "kr5_link_5 touches the table (-12 mm)"
    )
    assert "3.0 mm from the object" in Collision("bh_base", "object", 0.003).describe()
    assert Collision("kr5_base", "table", -1e-12).describe() == "kr5_base touches the table (0 mm)"
