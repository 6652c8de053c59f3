"""The kinematic test backend of graspframe.testing: it honours the backend contract, and
the planner and the executor carry out grasps on it without a simulator."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from graspframe.common.defaults import SCENE_OBJECT_XY
from graspframe.common.grasps import PALM
from graspframe.common.grasps import HumanGrasp as G
from graspframe.common.transforms import make_T
from graspframe.hal import ObjectDescription, WorldConfig
from graspframe.motion.arm_motion import ArmMotion
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.mounting import mount
from graspframe.strategy import method
from graspframe.strategy.arm_path import choose_plan
from graspframe.strategy.execution import ExecutionLog, GraspOutcome, run_policy
from graspframe.strategy.held_check import HeldTest
from graspframe.strategy.method import MethodStrategy
from graspframe.strategy.planner import PlanningTarget
from graspframe.strategy.reference_poses import reference_placement
from graspframe.testing import assert_backend_contract, backend_problems
from graspframe.testing.kinematic_backend import CONTACT_DISTANCE, KinematicBackend

REGISTRY = default_registry()
TIMESTEP = 0.01  # [s] one step per control cycle keeps these tests fast
STAGES_VOLAR = [
    "execute.preshape",
    "execute.pre_approach",
    "execute.approach",
    "execute.first_contact",
    "execute.closed",
    "execute.hold",
    "execute.lift",
    "execute.disturbance",
]


@pytest.mark.parametrize("hand_name", ["barrett", "karlsruhe"])
def test_the_kinematic_backend_honours_the_backend_contract(hand_name):
    assert_backend_contract(
        KinematicBackend,
        REGISTRY.get_hand(hand_name),
        REGISTRY.get_arm("kuka"),
        REGISTRY.get_object("large_cylinder"),
    )


class _IgnoresMounting(KinematicBackend):
    """Mounts the hand straight on the flange whatever the configuration says."""

    name = "ignores_mounting"

    def create_world(self, config):
        robot = mount(config.robot.arm, config.hand) if config.robot else None
        return super().create_world(dataclasses.replace(config, robot=robot))


def test_the_contract_catches_a_backend_that_ignores_the_mounted_robot():
    hand, arm = REGISTRY.get_hand("barrett"), REGISTRY.get_arm("kuka")
    problems = backend_problems(_IgnoresMounting, hand, arm, REGISTRY.get_object("large_cylinder"))
    assert len(problems) == 1 and "from where the mounted model" in problems[0]


def _run(
    hand_name: str, grasp: G, object_error=(0.0, 0.0), object_name: str | None = None
) -> tuple[GraspOutcome, list[tuple[str, dict]], object, ExecutionLog]:
    """Plan on the KUKA and execute on the kinematic backend, the robot believing the
    object `object_error` [m] (x, y) off where it stands; (outcome, events, plan, log)."""
    hand, arm = REGISTRY.get_hand(hand_name), REGISTRY.get_arm("kuka")
    obj = REGISTRY.get_object(object_name) if object_name else REGISTRY.default_object_for(grasp)
    placement = reference_placement(obj, REGISTRY.get_hand("human").preshape_for(grasp))
    T_world_object = make_T(p=[*SCENE_OBJECT_XY, obj.half_height])
    T_world_object_est = T_world_object.copy()
    T_world_object_est[:2, 3] += object_error
    target = PlanningTarget(grasp, placement.T_object_palm, T_world_object_est, hand, obj)
    checked = choose_plan(target, arm, np.eye(4))
    config = WorldConfig(
        hand=hand,
        object=obj,
        robot=checked.robot,
        T_world_arm_base=checked.T_world_base,
        T_world_object=T_world_object,
        timestep=TIMESTEP,
    )
    events: list[tuple[str, dict]] = []
    log = ExecutionLog(emit=lambda kind, **data: events.append((kind.name, data)))
    with KinematicBackend().create_world(config) as world:
        motion = ArmMotion(world, checked.robot, checked.T_world_base)
        outcome = run_policy(
            world,
            motion,
            MethodStrategy(checked.plan, hand, obj),
            obj,
            HeldTest(),
            log,
        )
    return outcome, events, checked.plan, log


def _stages(events) -> list[str]:
    return [kind for kind, _ in events if kind != "execute.snapshot"]


@pytest.mark.parametrize("hand_name", ["barrett", "karlsruhe"])
def test_a_volar_grasp_stops_at_the_palm_contact_closes_and_lifts(hand_name):
    outcome, events, plan, log = _run(hand_name, G.LARGE_DIAMETER)
    assert plan.volar
    assert _stages(events) == STAGES_VOLAR
    (approach,) = [data for kind, data in events if kind == "execute.approach"]
    (first_contact,) = [data for kind, data in events if kind == "execute.first_contact"]
    assert approach["stopped"] and first_contact["on_palm"]
    # The approach stopped short of its goal plus the overshoot allowed past it.
    assert approach["travel"] < plan.pre_approach_distance
    assert outcome.success, outcome.failure_reason
    assert outcome.corrections == 0 and outcome.palm_contact
    assert PALM in outcome.touching_fingers and len(outcome.touching_fingers) >= 3
    assert outcome.object_rise == pytest.approx(outcome.lift_height, abs=1e-3)
    # Like a hardware backend, the kinematic one cannot push the object.
    assert outcome.held_under_disturbance is None
    assert "cannot push" in outcome.disturbance_skipped
    labels = [data["label"] for kind, data in events if kind == "execute.snapshot"]
    assert labels == ["first contact", "hold", "after lift"]
    # The log keeps the same moments for pictures, with the contacts at each.
    assert [moment.label for moment in log.moments] == labels
    assert {c.real_finger for c in log.moments[1].contacts} == set(outcome.touching_fingers)


def test_a_volar_approach_meeting_a_finger_first_corrects_towards_the_object():
    error = np.array([0.0, 0.03])  # the object stands 3 cm to the -y of the belief
    outcome, events, _, _ = _run("barrett", G.LARGE_DIAMETER, object_error=error)
    first_contacts = [data for kind, data in events if kind == "execute.first_contact"]
    corrections = [data for kind, data in events if kind == "execute.correction"]
    assert not first_contacts[0]["on_palm"] and first_contacts[-1]["on_palm"]
    assert corrections[0]["reason"] == "finger first"
    shift = corrections[0]["goal_after"] - corrections[0]["goal_before"]
    assert shift[1] < -0.005 and shift[2] == 0.0  # towards the object, height kept
    assert outcome.corrections == len(corrections) >= 1
    assert outcome.success, outcome.failure_reason


def test_a_non_volar_grasp_approaches_without_feedback():
    outcome, events, plan, _ = _run("barrett", G.POWER_SPHERE)
    assert not plan.volar
    assert "execute.first_contact" not in _stages(events)
    (approach,) = [data for kind, data in events if kind == "execute.approach"]
    assert not approach["stopped"]
    assert approach["travel"] == pytest.approx(plan.pre_approach_distance, abs=1e-3)
    assert outcome.corrections == 0
    assert outcome.success, outcome.failure_reason


def test_a_volar_approach_that_meets_nothing_reports_it_and_fails():
    outcome, events, _, _ = _run("barrett", G.LARGE_DIAMETER, object_error=(0.0, 0.25))
    stages = _stages(events)
    assert "execute.no_contact" in stages and "execute.first_contact" not in stages
    assert not outcome.success


def test_fingers_stop_on_the_object_and_the_barrett_clutch_breaks_away():
    """The free Barrett hand closes its wrap around a wide can: each finger stops on the
    can, its proximal joint held by the breakaway clutch; no finger goes into the can."""
    hand = REGISTRY.get_hand("barrett")
    radius = 0.055
    can = ObjectDescription("wide_can", "cylinder", {"radius": radius, "length": 0.12}, 0.3)
    config = WorldConfig(
        hand=hand, object=can, T_world_object=make_T(p=[0.0, 0.0, 0.06]), timestep=TIMESTEP
    )
    world = KinematicBackend().create_world(config)
    R_world_palm = np.column_stack([[0, 1, 0], [0, 0, 1], [1, 0, 0]]).astype(float)
    # Fingers straight (the hand starts at zero), facing the can from -x, 5 mm off its side.
    world.hand.set_free_pose(make_T(R_world_palm, [-radius - 0.005, 0.0, 0.06]))
    wrap = hand.preshape("wrap")
    assert world.hand.contacts() == []
    world.hand.set_joint_targets(wrap.closed_q)
    world.step(round(2.0 / TIMESTEP))
    held = world.hand.held_leaders
    assert set(held) == {"bh_f1_prox", "bh_f2_prox", "bh_f3_prox"}
    q = world.hand.joint_positions()
    for prox, q_held in held.items():
        assert q_held < math.radians(80) and q[prox] == q_held
    contacts = world.hand.contacts()
    assert {c.real_finger for c in contacts} >= {"finger_1", "finger_2", "finger_3"}
    # Fingers stop at the surface: the deepest is within the touch distance.
    depth = max(np.linalg.norm(c.f) for c in contacts)
    assert depth < 1.0 + 1000.0 * CONTACT_DISTANCE
    assert world.object.T_world_object() == pytest.approx(config.T_world_object)


def test_the_kinematic_world_is_deterministic():
    def final_state():
        outcome, _, _, _ = _run("barrett", G.POWER_SPHERE)
        return outcome.T_world_object_at_hold, [c.p for c in outcome.contacts]

    (T_first, points_first), (T_second, points_second) = final_state(), final_state()
    assert np.array_equal(T_first, T_second)
    assert np.array_equal(np.array(points_first), np.array(points_second))


def test_the_corrections_the_executor_drives_come_from_the_segment_builder(monkeypatch):
    """The volar loop's retreat and corrected approach are built by segments.py (as the
    executor imports them): what the builder returns is what the arm follows."""
    built_retreat, built_approach = method.retreat_line, method.approach_line
    followed: list[str] = []
    follow = ArmMotion.follow

    def recording_follow(self, line, *args, **kwargs):
        followed.append(line.name)
        return follow(self, line, *args, **kwargs)

    def tagged(builder, tag):
        return lambda *a, **k: dataclasses.replace(builder(*a, **k), name=tag)

    monkeypatch.setattr(ArmMotion, "follow", recording_follow)
    monkeypatch.setattr(method, "retreat_line", tagged(built_retreat, "built retreat"))
    monkeypatch.setattr(method, "approach_line", tagged(built_approach, "built approach"))
    outcome, _, _, _ = _run("barrett", G.LARGE_DIAMETER, object_error=np.array([0.0, 0.03]))
    assert outcome.corrections >= 1
    assert followed.count("built retreat") == outcome.corrections
    assert followed.count("built approach") == outcome.corrections
    # A retreat is followed by the approach to the corrected goal.
    assert followed[followed.index("built retreat") + 1] == "built approach"


def test_a_changed_builder_changes_the_retreat_the_executor_drives(monkeypatch):
    """A retreat built 2 cm shorter by segments.py is 2 cm shorter where the arm drives it."""
    built_retreat = method.retreat_line
    retreats: list[float] = []

    def shorter(*args, **kwargs):
        line = built_retreat(*args, **kwargs)
        return dataclasses.replace(line, distance=line.distance - 0.02)

    follow = ArmMotion.follow

    def recording_follow(self, line, *args, **kwargs):
        result = follow(self, line, *args, **kwargs)
        if line.name == "retreat":
            retreats.append((line.distance, result.travel))
        return result

    monkeypatch.setattr(ArmMotion, "follow", recording_follow)
    error = np.array([0.0, 0.03])
    _run("barrett", G.LARGE_DIAMETER, object_error=error)
    (planned, driven), *_ = retreats
    monkeypatch.setattr(method, "retreat_line", shorter)
    retreats.clear()
    _run("barrett", G.LARGE_DIAMETER, object_error=error)
    (planned_shorter, driven_shorter), *_ = retreats
    assert planned_shorter == pytest.approx(planned - 0.02)
    assert driven_shorter == pytest.approx(driven - 0.02, abs=1e-3)
