"""The simulator keeps the model: joint limits hold when the hand is driven into the
table, the floating base holds the palm at its setpoint under a grasp's loads, and a run
whose joint passes its limit says so (the event, result.json, the run summary)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pytest
from graspframe_sapien.world import SapienBackend
from rich.console import Console

from graspframe.checks.grasps import design_object, hand_alone_setup
from graspframe.cli.run_summary import print_run_summary
from graspframe.common.cache import read_entry, write_entry
from graspframe.common.contacts import Contact
from graspframe.common.grasps import HumanGrasp
from graspframe.common.json_files import jsonable
from graspframe.common.transforms import R_from_rpy, inv_T, make_T
from graspframe.hal import HandDescription, JointSpec, ObjectDescription, World, WorldConfig
from graspframe.model_files.urdf_model import UrdfModel
from graspframe.motion.arm_motion import ArmMotion
from graspframe.motion.joint_limits import (
    TOLERANCE_DEG,
    JointLimitMonitor,
    LimitExcess,
)
from graspframe.plugin_system import events
from graspframe.plugin_system.registry import default_registry
from graspframe.robot_models.floating_base import (
    PALM_ORIENTATION_ACCURACY,
    PALM_POSITION_ACCURACY,
    mount_floating,
)
from graspframe.run.request import RunRequest
from graspframe.run.result import RunResult, Score
from graspframe.strategy.execution import Execution, ExecutionLog, Grip, execute
from graspframe.strategy.held_check import HeldTest, HeldVerdict
from graspframe.strategy.human_reference import HumanReference, _cached_reference
from graspframe.strategy.method import MethodStrategy

REGISTRY = default_registry()
PRESS_SPEED = 0.05  # [m/s] of the palm driven down
START_HEIGHT = 0.10  # [m] of the palm above the table
PRESS_TRAVEL = 0.12  # [m]: 2 cm below the table top, where nothing can follow
FAR_OBJECT = ObjectDescription(
    "far_box", "box", {"size_x": 0.03, "size_y": 0.03, "size_z": 0.03}, mass=0.05
)


@dataclass(frozen=True)
class PressIntoTable:
    """A grasp policy for these tests: the hand takes `posture_deg`, then the floating base
    drives the palm PRESS_TRAVEL down, into the table top."""

    posture_deg: dict[str, float]

    def grasp(self, world: World, motion: ArmMotion, log: ExecutionLog) -> Grip:
        world.hand.set_joint_targets({j: math.radians(v) for j, v in self.posture_deg.items()})
        motion.idle(round(0.6 / world.timestep))
        down = np.array([0.0, 0.0, -1.0])
        motion.move_palm_linear(down, PRESS_TRAVEL, PRESS_SPEED, stop_on_contact=False)
        motion.idle(round(0.5 / world.timestep))
        return Grip()


@dataclass
class Heard:
    """The events an execution emitted, by kind name."""

    events: list[tuple[str, dict]] = field(default_factory=list)

    def __call__(self, kind: events.EventKind, **data: object) -> None:
        self.events.append((kind.name, data))

    def of(self, kind: events.EventKind) -> list[dict]:
        return [data for name, data in self.events if name == kind.name]


@dataclass(frozen=True)
class Press:
    """A hand in a posture [deg], its palm facing the table turned by roll and pitch
    [deg] (180, 0: straight down), driven into the table."""

    hand: str
    posture_deg: dict[str, float]
    roll_pitch_deg: tuple[float, float]


def _press(hand: HandDescription, press: Press, heard: Heard) -> tuple[Execution, list[float]]:
    """The execution of `press` on the floating base (the object stands well away), and
    the palm's height above the table [m] every control cycle."""
    roll, pitch = (math.radians(a) for a in press.roll_pitch_deg)
    T_world_palm = make_T(R_from_rpy(roll, pitch, 0.0), [0.3, 0.0, START_HEIGHT])
    robot, T_world_base = mount_floating(hand, T_world_palm)
    config = WorldConfig(
        hand=hand,
        object=FAR_OBJECT,
        robot=robot,
        T_world_arm_base=T_world_base,
        T_world_object=make_T(p=[0.6, 0.3, 0.015]),
    )
    heights: list[float] = []
    execution = execute(
        SapienBackend(),
        config,
        PressIntoTable(press.posture_deg),
        HeldTest(disturb=False),
        emit=heard,
        on_cycle=lambda motion: heights.append(motion.world.hand.T_world_palm()[2, 3]),
    )
    return execution, heights


# [kg m^2] on every finger joint: with it these presses keep the limits (docs/robots.md,
# "Joint limits and drives in the simulator").
FINGER_ARMATURE = 1.0e-3


def _with_armature(hand: HandDescription, armature: float) -> HandDescription:
    return replace(hand, drive=replace(hand.drive, armature=armature))


# Presses that crush a finger between the palm and the table: with the built-in drives
# (no armature) the simulator moved a joint past its limit by 111 deg (human thumb IP),
# 19 deg (Barrett distal), 21 deg (Karlsruhe index); with FINGER_ARMATURE by 0.3 deg.
CRUSHES = {
    "human": Press("human", {"hh_thumb_cmc_abd": 90.0, "hh_thumb_cmc_flex": -10.0}, (180, 0)),
    "barrett": Press(
        "barrett",
        {"bh_spread_1": 90.0, "bh_f1_prox": 20.0, "bh_f2_prox": 20.0, "bh_f3_prox": 20.0},
        (150, 0),
    ),
    "karlsruhe": Press(
        "karlsruhe",
        {"kh_thumb_flex": 45.0, "kh_index_prox": 45.0, "kh_ring": 45.0},
        (180, 40),
    ),
}
# Presses of the fingertips on the table that the built-in drives hold within their
# limits (the Barrett's distal joints pass theirs once lifted off such a press: the
# crushes below, and a finger armature, cover it; its fingers on an object are held in
# the floating-base test).
PRESSES = {
    "human": Press(
        "human", {"hh_index_mcp": 30.0, "hh_middle_mcp": 30.0, "hh_thumb_cmc_abd": 30.0}, (180, 0)
    ),
    "karlsruhe": Press(
        "karlsruhe",
        {"kh_index_prox": 30.0, "kh_middle_prox": 30.0, "kh_thumb_flex": 30.0},
        (180, 0),
    ),
}


def _assert_pressed(heights: list[float]) -> None:
    """The table stopped the hand: the palm came down, but not as far as its setpoint."""
    assert START_HEIGHT - 0.02 > min(heights) > START_HEIGHT - PRESS_TRAVEL + 0.01


@pytest.mark.parametrize("hand_name", sorted(PRESSES))
def test_joint_limits_hold_with_the_fingertips_pressed_on_the_table(hand_name):
    heard = Heard()
    execution, heights = _press(REGISTRY.get_hand(hand_name), PRESSES[hand_name], heard)
    _assert_pressed(heights)
    report = execution.joint_limits
    assert report.largest_excess_deg < TOLERANCE_DEG, [e.describe() for e in report.excesses]
    assert not heard.of(events.EXECUTE_JOINT_LIMIT)


@pytest.mark.parametrize("hand_name", sorted(CRUSHES))
def test_a_finger_armature_keeps_the_limits_of_a_finger_crushed_on_the_table(hand_name):
    hand = REGISTRY.get_hand(hand_name)
    assert hand.drive.armature == 0.0  # the built-in drives: the crush breaks a limit
    broken, heights = _press(hand, CRUSHES[hand_name], Heard())
    _assert_pressed(heights)
    assert broken.joint_limits.largest_excess_deg > 5 * TOLERANCE_DEG
    heard = Heard()
    kept, _heights = _press(_with_armature(hand, FINGER_ARMATURE), CRUSHES[hand_name], heard)
    report = kept.joint_limits
    assert report.largest_excess_deg < TOLERANCE_DEG, [e.describe() for e in report.excesses]
    assert not heard.of(events.EXECUTE_JOINT_LIMIT)


def test_a_joint_past_its_limit_is_reported_in_the_event_the_result_and_the_summary(
    tmp_path,
):
    # Crushed on the table, the human thumb passes its limit.
    heard = Heard()
    execution, _heights = _press(REGISTRY.get_hand("human"), CRUSHES["human"], heard)

    (violation, *_) = execution.joint_limits.violations
    assert violation.joint.startswith("hh_thumb")
    assert math.degrees(violation.excess) > TOLERANCE_DEG
    reported = heard.of(events.EXECUTE_JOINT_LIMIT)
    assert violation.joint in [data["joint"] for data in reported]
    assert len(reported) == len({data["joint"] for data in reported})  # once per joint

    result = RunResult(
        run_id="press",
        request=RunRequest(hand="human"),
        versions={},
        result_path=Path(tmp_path) / "result.json",
        status="ok",
        execution=execution,
    )
    joint_limits = result.to_json()["joint_limits"]
    assert joint_limits["violations"][0]["joint"] == violation.joint
    assert joint_limits["violations"][0]["excess_deg"] == pytest.approx(
        math.degrees(violation.excess)
    )
    assert joint_limits["largest_excess_deg"] >= joint_limits["violations"][0]["excess_deg"]
    console = Console(record=True, width=200)
    print_run_summary(result, console)
    summary = console.export_text()
    assert f"broke a joint limit: {violation.joint}" in summary


def _heaviest_design_object(hand: HandDescription):
    """(grasp, preshape) whose design object is the heaviest of the hand's."""
    candidates = [
        (design_object(hand.preshape(name)).mass, grasp)
        for grasp, name in hand.grasp_map.items()
        if hand.preshape(name).design_object is not None
    ]
    _mass, grasp = max(candidates, key=lambda item: item[0])
    return grasp, hand.preshape_for(grasp)


@pytest.mark.parametrize("hand_name", ["barrett", "karlsruhe"])
def test_the_floating_base_holds_the_palm_as_near_its_setpoint_as_it_says(hand_name):
    hand = REGISTRY.get_hand(hand_name)
    grasp, _preshape = _heaviest_design_object(hand)
    setup = hand_alone_setup(hand, grasp)
    checked, config, obj = setup.checked, setup.config, setup.obj
    heard = Heard()
    errors: list[tuple[float, float]] = []  # [m], [rad] of the palm, setpoint still

    def measure(motion: ArmMotion) -> None:
        closed = bool(heard.of(events.EXECUTE_CLOSED))
        if not (closed and motion.trajectory.finished and motion.trajectory.at_rest):
            return
        T_world_setpoint = motion.T_world_base @ motion.ik.forward_palm(motion.trajectory.q)
        T_setpoint_palm = inv_T(T_world_setpoint) @ motion.world.hand.T_world_palm()
        cos_angle = (np.trace(T_setpoint_palm[:3, :3]) - 1.0) / 2.0
        angle = math.acos(float(np.clip(cos_angle, -1.0, 1.0)))
        errors.append((float(np.linalg.norm(T_setpoint_palm[:3, 3])), angle))

    execution = execute(
        SapienBackend(),
        config,
        MethodStrategy(checked.plan, hand, obj),
        HeldTest(),
        emit=heard,
        on_cycle=measure,
    )
    outcome = execution.outcome
    assert outcome.success, outcome.failure_reason  # loaded: held through lift and pushes
    assert execution.joint_limits.largest_excess_deg < TOLERANCE_DEG  # fingers on it too
    assert len(errors) > 100  # the hold, the settling after the lift and the pushes
    position_error = max(e[0] for e in errors)
    orientation_error = max(e[1] for e in errors)
    assert position_error < PALM_POSITION_ACCURACY, f"{1000 * position_error:.3f} mm"
    assert orientation_error < PALM_ORIENTATION_ACCURACY, (
        f"{math.degrees(orientation_error):.4f} deg"
    )


def _model(joints: str) -> UrdfModel:
    links = "".join(f'<link name="l{i}"/>' for i in range(4))
    return UrdfModel("probe", f'<robot name="probe">{links}{joints}</robot>')


def test_the_monitor_keeps_each_joints_largest_excess_and_tells_a_new_violation_once():
    model = _model(
        '<joint name="hinge" type="revolute"><parent link="l0"/><child link="l1"/>'
        '<limit lower="-0.5" upper="1.0" effort="1" velocity="1"/></joint>'
        '<joint name="slide" type="prismatic"><parent link="l1"/><child link="l2"/>'
        '<limit lower="0" upper="0.1" effort="1" velocity="1"/></joint>'
        '<joint name="spin" type="continuous"><parent link="l2"/><child link="l3"/></joint>'
    )
    monitor = JointLimitMonitor(model)
    assert set(monitor.limits) == {"hinge", "slide"}  # a continuous joint has no limits
    over = math.radians(TOLERANCE_DEG + 1.0)
    assert monitor.check(0.1, {"hinge": 0.9, "slide": 0.05, "spin": 40.0}) == []
    monitor.stage = "execute.closed"
    (first,) = monitor.check(0.2, {"hinge": -0.5 - over, "slide": 0.1005})
    assert (first.joint, first.stage, first.sim_time) == ("hinge", "execute.closed", 0.2)
    assert monitor.check(0.3, {"hinge": -0.5 - 2 * over, "slide": 0.1025}) == [
        e for e in monitor.report().excesses if e.joint == "slide"
    ]
    monitor.check(0.4, {"hinge": -0.5 - over})  # less than before: the largest stays
    report = monitor.report()
    assert [e.joint for e in report.excesses] == ["hinge", "slide"]
    assert report.largest_excess_deg == pytest.approx(math.degrees(2 * over))
    slide = report.to_json()["excesses"][1]
    assert slide["joint"] == "slide" and slide["excess_mm"] == pytest.approx(2.5)
    assert [e.joint for e in report.violations] == ["hinge", "slide"]


def test_the_human_references_violations_are_cached_and_reported(tmp_path):
    limit = JointSpec("hh_thumb_ip", math.radians(-20.0), math.radians(80.0), 1.0, 1.0)
    violation = LimitExcess(limit, math.radians(91.0), math.radians(-111.0), 1.5, "execute.closed")
    obj = REGISTRY.get_object("large_cylinder")
    reference = HumanReference(
        HumanGrasp.LARGE_DIAMETER,
        obj.name,
        (Contact("hh_palm", "palm", np.zeros(3), np.array([0, 0, 1.0]), np.zeros(3)),),
        "simulated",
        HeldVerdict(True, True, None),
        joint_limit_violations=(violation,),
    )
    entry = write_entry(Path(tmp_path) / "reference", jsonable(reference.to_json()), {})
    cached = _cached_reference(read_entry(entry.folder), obj)
    assert cached.joint_limit_violations == (violation,)  # every field, as it was

    score = Score(
        "cache", ("palm",), cached.held, (), (), human_joint_limit_violations=(violation,)
    )
    assert score.to_json()["human_joint_limit_violations"] == [violation.to_dict()]
    result = RunResult(
        run_id="human",
        request=RunRequest(hand="human"),
        versions={},
        result_path=entry.folder,
        score=score,
    )
    console = Console(record=True, width=200)
    print_run_summary(result, console)
    assert "joint limit of the human reference: hh_thumb_ip past it by 91.0 deg" in (
        console.export_text()
    )


def test_an_excess_reads_back_from_its_json_and_from_an_older_entrys():
    """A cached human reference keeps its excesses as JSON: the limit as a JointSpec
    (infinite motion limits as null), or, in an older entry, as {joint, lower, upper,
    prismatic}."""
    limit = JointSpec("slide", 0.0, 0.1, math.inf, math.inf)
    excess = LimitExcess(limit, 0.0025, 0.1025, 0.3, "execute.closed", prismatic=True)
    assert LimitExcess.from_json(jsonable(excess)) == excess
    older = {
        "limit": {"joint": "slide", "lower": 0.0, "upper": 0.1, "prismatic": True},
        "excess": 0.0025,
        "position": 0.1025,
        "sim_time": 0.3,
        "stage": "execute.closed",
    }
    assert LimitExcess.from_json(older) == excess
    assert excess.to_dict()["excess_mm"] == pytest.approx(2.5)
