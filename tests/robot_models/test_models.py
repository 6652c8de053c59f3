"""Every built-in hand and arm model, in Pinocchio and in SAPIEN, alone and mounted.

Parametrised over the registry, so a new built-in model is covered without editing
this file. The models of a third-party plugin installed beside graspframe are its own
to test (the contract tests, `graspframe check-hand`), not this suite's.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from graspframe_sapien.articulation import active_joints, create_scene, load_articulation
from graspframe_sapien.backend import SapienBackend

from graspframe.common.errors import GraspframeError, UnknownNameError
from graspframe.common.transforms import R_from_rpy, make_T
from graspframe.hal import WorldConfig
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.model import (
    CollisionModel,
    collision_geometry_model,
    load_pinocchio_model,
    model_of,
    summarize_urdf,
)
from graspframe.robot_models.mounting import mount

REGISTRY = default_registry()
BUILT_IN_PACKAGE = "graspframe"
HANDS = [entry.name for entry in REGISTRY.entries("hand") if entry.package == BUILT_IN_PACKAGE]
ARMS = [entry.name for entry in REGISTRY.entries("arm") if entry.package == BUILT_IN_PACKAGE]
PRESHAPES = [(h, p) for h in HANDS for p in REGISTRY.get_hand(h).preshapes]
DESCRIPTIONS = [("hand", h) for h in HANDS] + [("arm", a) for a in ARMS]

# Joint limits: SAPIEN stores them as float32.
LIMIT_TOL = 1e-5  # [rad]


def _sapien_limits(model, fix_root=True):
    scene = create_scene(1 / 500)
    articulation = load_articulation(scene, model, fix_root=fix_root)
    names = list(active_joints(articulation))
    return dict(zip(names, np.asarray(articulation.get_qlimits()), strict=True))


def test_builtin_models_are_registered():
    assert {"barrett", "karlsruhe", "human"} <= set(HANDS)
    assert {"kuka", "kuka_iiwa14"} <= set(ARMS)


@pytest.mark.parametrize(("kind", "name"), DESCRIPTIONS)
def test_model_has_same_joints_and_limits_in_pinocchio_and_sapien(kind, name):
    description = REGISTRY.entry(kind, name).item
    urdf = summarize_urdf(model_of(description))
    sapien_limits = _sapien_limits(model_of(description))
    assert sorted(sapien_limits) == sorted(urdf.joints)
    for joint_name, joint in urdf.joints.items():
        lower, upper = sapien_limits[joint_name]
        assert lower == pytest.approx(joint.lower, abs=LIMIT_TOL), joint_name
        assert upper == pytest.approx(joint.upper, abs=LIMIT_TOL), joint_name


@pytest.mark.parametrize("arm_name", ARMS)
@pytest.mark.parametrize("hand_name", HANDS)
def test_every_hand_mounts_on_every_arm(hand_name, arm_name):
    import pinocchio as pin

    arm, hand = REGISTRY.get_arm(arm_name), REGISTRY.get_hand(hand_name)
    T_flange_hand = make_T(R_from_rpy(0.0, 0.0, math.pi / 4), [0.0, 0.0, 0.01])
    robot = mount(arm, hand, T_flange_hand)

    combined = summarize_urdf(robot.model)
    alone = set(summarize_urdf(model_of(arm)).joints) | set(summarize_urdf(model_of(hand)).joints)
    assert set(combined.joints) == alone
    assert sorted(_sapien_limits(robot.model)) == sorted(alone)

    # The palm sits where flange pose x mount transform x hand-alone palm pose puts it.
    model = load_pinocchio_model(robot.model)
    data = model.createData()
    q = pin.neutral(model)
    for joint_name, value in zip(arm.joint_names, arm.home_q, strict=True):
        q[model.joints[model.getJointId(joint_name)].idx_q] = value
    pin.framesForwardKinematics(model, data, q)
    T_base_flange = data.oMf[model.getFrameId(arm.flange_link)].homogeneous
    T_base_palm = data.oMf[model.getFrameId(hand.palm_frame)].homogeneous
    hand_alone = CollisionModel(model_of(hand))
    T_hand_palm = hand_alone.T_root_frame(hand.palm_frame)
    np.testing.assert_allclose(T_base_palm, T_base_flange @ T_flange_hand @ T_hand_palm, atol=1e-9)


MOUNTINGS = [(h, m) for h in HANDS for m in REGISTRY.get_hand(h).mountings]


@pytest.mark.parametrize(("hand_name", "mounting_name"), MOUNTINGS)
def test_a_hand_mounts_through_its_adapters(hand_name, mounting_name):
    import pinocchio as pin

    arm, hand = REGISTRY.get_arm("kuka"), REGISTRY.get_hand(hand_name)
    mounting = hand.mounting(mounting_name)
    robot = mount(arm, hand, mounting=mounting_name)
    assert robot.mounting == mounting_name
    np.testing.assert_allclose(robot.T_flange_hand, mounting.T_flange_hand)
    with pytest.raises(GraspframeError, match="differs"):
        mount(arm, hand, np.eye(4), mounting=mounting_name)

    # The adapter is one more link, fixed to the hand's root, with the adapter's shapes
    # where the mounting puts them; the simulator loads the same joints.
    adapter_link = f"{hand.root_link}_adapter"
    combined = summarize_urdf(robot.model)
    assert adapter_link in combined.links
    assert sorted(_sapien_limits(robot.model)) == sorted(combined.joints)
    pinocchio_model = load_pinocchio_model(robot.model, mimic=False)
    data = pinocchio_model.createData()
    q = pin.neutral(pinocchio_model)
    for joint_name, value in zip(arm.joint_names, arm.home_q, strict=True):
        q[pinocchio_model.joints[pinocchio_model.getJointId(joint_name)].idx_q] = value
    pin.framesForwardKinematics(pinocchio_model, data, q)
    T_base_flange = data.oMf[pinocchio_model.getFrameId(arm.flange_link)].homogeneous
    T_base_root = data.oMf[pinocchio_model.getFrameId(hand.root_link)].homogeneous
    # The URDF holds 9 significant digits: a quarter turn is off by ~4e-9 rad.
    np.testing.assert_allclose(T_base_root, T_base_flange @ mounting.T_flange_hand, atol=1e-8)
    geometry = collision_geometry_model(robot.model, pinocchio_model)
    geometry_data = pin.GeometryData(geometry)
    pin.updateGeometryPlacements(pinocchio_model, data, geometry, geometry_data, q)
    placed = [
        geometry_data.oMg[k].homogeneous
        for k, g in enumerate(geometry.geometryObjects)
        if pinocchio_model.frames[g.parentFrame].name == adapter_link
    ]
    assert len(placed) == len(mounting.adapter)
    for T_base_shape, shape in zip(placed, mounting.adapter, strict=True):
        np.testing.assert_allclose(T_base_shape, T_base_root @ shape.T_root_shape, atol=1e-8)


def test_an_unknown_mounting_is_named():
    hand = REGISTRY.get_hand("barrett")
    with pytest.raises(UnknownNameError, match="mounting"):
        mount(REGISTRY.get_arm("kuka"), hand, mounting="no_such_adapter")


@pytest.mark.parametrize(("hand_name", "preshape_name"), PRESHAPES)
def test_open_preshape_is_within_limits_and_free_of_self_collision(hand_name, preshape_name):
    hand = REGISTRY.get_hand(hand_name)
    preshape = hand.preshapes[preshape_name]
    for joint_name, value in preshape.open_q.items():
        assert hand.joint(joint_name).contains(value), joint_name
    model = CollisionModel(model_of(hand))
    model.place(hand.with_model_followers(preshape.open_q))
    assert model.colliding_links() == []


def _close_in_free_space(hand, preshape):
    """Open preshape, then command the closed targets with nothing to touch, through the
    SAPIEN hand driver (velocity-limited setpoints, couplings); returns the measured
    actuated joint positions [rad] by name."""
    world = SapienBackend().create_world(WorldConfig(hand=hand, object=None))
    world.hand.set_free_pose(make_T(p=[0.0, 0.0, 0.5]))  # well above the table
    world.teleport_hand(dict(preshape.open_q))
    world.hand.set_joint_targets(preshape.closed_q)
    travel_time = max(
        abs(preshape.closed_q[j.name] - preshape.open_q.get(j.name, 0.0)) / j.max_velocity
        for j in hand.joints
        if j.name in preshape.closed_q
    )
    world.step(round((travel_time + 1.0) / world.timestep))  # + 1 s to settle
    return world.hand.joint_positions()


# Soft (fluidic) drives settle with a small gravity sag; 2 deg is far below any preshape
# difference and above the sag of the softest built-in hand.
CLOSE_TOL = math.radians(2.0)


@pytest.mark.parametrize(("hand_name", "preshape_name"), PRESHAPES)
def test_closing_in_free_space_reaches_the_closed_configuration(hand_name, preshape_name):
    hand = REGISTRY.get_hand(hand_name)
    preshape = hand.preshapes[preshape_name]
    q = _close_in_free_space(hand, preshape)
    for joint_name, target in preshape.closed_q.items():
        assert q[joint_name] == pytest.approx(target, abs=CLOSE_TOL), joint_name


def _colliding_links_pair_by_pair(model: CollisionModel) -> list[tuple[str, str]]:
    """colliding_links without its bounding-sphere test: coal on every pair."""
    import coal

    placed = list(model.shapes())
    hits = set()
    for i, (link_a, shape_a, T_a) in enumerate(placed):
        for link_b, shape_b, T_b in placed[i + 1 :]:
            if link_a == link_b or link_b in (model.parent_link(link_a),):
                continue
            if model.parent_link(link_b) == link_a:
                continue
            tf_a = coal.Transform3s(T_a[:3, :3], T_a[:3, 3])
            tf_b = coal.Transform3s(T_b[:3, :3], T_b[:3, 3])
            if coal.collide(
                shape_a, tf_a, shape_b, tf_b, coal.CollisionRequest(), coal.CollisionResult()
            ):
                hits.add(tuple(sorted((link_a, link_b))))
    return sorted(hits)


@pytest.mark.parametrize("hand_name", HANDS)
def test_colliding_links_finds_what_coal_finds_pair_by_pair(hand_name):
    """The bounding spheres that skip far pairs skip no overlapping pair: at random
    postures (many of them self-colliding), the same pairs as coal on every pair."""
    hand = REGISTRY.get_hand(hand_name)
    model = CollisionModel(model_of(hand))
    rng = np.random.default_rng(0)
    overlapping = 0
    for _ in range(20):
        q = {j.name: rng.uniform(j.lower, j.upper) for j in hand.joints}
        model.place(hand.with_model_followers(q))
        expected = _colliding_links_pair_by_pair(model)
        assert model.colliding_links() == expected, q
        overlapping += bool(expected)
    assert overlapping > 0  # the postures tried do overlap somewhere
