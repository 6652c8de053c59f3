"""One held test for the robot and the human reference: its criteria set in one place
judge both (graspframe/strategy/held_check.py)."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

from graspframe.common.errors import InputError, MotionError
from graspframe.common.grasps import HumanGrasp
from graspframe.common.json_files import jsonable
from graspframe.plugin_system.registry import default_registry
from graspframe.run.request import RunRequest
from graspframe.run.result import outcome_json
from graspframe.run.runner import run_grasp
from graspframe.strategy.execution import run_policy
from graspframe.strategy.held_check import HeldTest, HeldVerdict, InHandMotion


def test_a_lift_height_set_once_judges_the_robot_and_the_human(tmp_path, monkeypatch):
    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(tmp_path / "cache"))  # a fresh reference
    judged: list[float] = []
    original = HeldTest.run

    def spy(self, world, motion, obj, after_lift=lambda _lifted: None):
        judged.append(self.lift_height)
        return original(self, world, motion, obj, after_lift)

    monkeypatch.setattr(HeldTest, "run", spy)
    request = RunRequest(
        hand="barrett",
        grasp=HumanGrasp.PINCH,
        mount="floating",
        out_root=str(tmp_path / "runs"),
        record=False,
        lift_height=0.03,
        disturbance_fraction=0.0,
    )
    result = run_grasp(request, default_registry()).to_json()
    # The robot's grasp, then the human reference's: both lifted 3 cm.
    assert judged == [0.03, 0.03]
    outcome = result["outcome"]
    assert outcome["lift_height"] == 0.03
    assert outcome["held_after_lift"] and outcome["object_rise"] == pytest.approx(0.03, abs=0.005)
    assert "--lift-height-mm 30" in result["reproduce"]
    # A push of no force is not a passed disturbance test: it is reported as not run.
    assert outcome["held_under_disturbance"] is None
    assert outcome["disturbance_skipped"] == "disturbance fraction 0"


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"lift_height": 0.0}, r"lift height 0 mm is outside \(0, 300\] mm"),
        ({"disturbance_fraction": -0.5}, r"disturbance fraction -0.5 is outside \[0, 5\]"),
    ],
)
def test_a_held_test_outside_its_range_is_refused(fields, message):
    with pytest.raises(InputError, match=message):
        RunRequest(hand="barrett", grasp=HumanGrasp.PINCH, **fields).held_test()


def test_the_bounds_and_the_words_follow_the_criteria():
    strict = HeldTest(max_shift_in_hand=0.005, max_turn_in_hand_deg=5.0)
    motion = InHandMotion(shift=0.01, turn_deg=2.0)
    assert HeldTest().within_bounds(motion) and not strict.within_bounds(motion)
    assert strict.first_slip({"+x": InHandMotion(0.0, 1.0), "-y": motion}) == ("-y", motion)
    words = strict.disturbance_failure({"-y": motion})
    assert words is not None and "(allowed 5 mm, 5 deg)" in words
    assert "of the hand's 30 mm" in HeldTest(lift_height=0.03).lift_failure(0.01, None)


def test_a_held_verdict_reads_back_every_field_from_its_json():
    """A cached human reference keeps the whole verdict: the lift, the pushes, the
    fingers, not only whether it held."""
    verdict = HeldVerdict(
        after_lift=True,
        under_disturbance=False,
        failure="the object slipped under the disturbance",
        object_rise=0.0483,
        lift_height=0.03,
        lift_motion=InHandMotion(0.0012, 1.5),
        disturbance={"+x": InHandMotion(0.001, 0.5), "-x": InHandMotion(0.025, 12.0)},
        fingers_after_lift=("index", "thumb"),
    )
    read_back = HeldVerdict.from_json(json.loads(json.dumps(jsonable(verdict))))
    assert read_back == verdict
    skipped = HeldVerdict(False, None, "slipped", disturbance_skipped="the lift failed")
    assert HeldVerdict.from_json(json.loads(json.dumps(jsonable(skipped)))) == skipped


class _Unreachable:
    def grasp(self, world, motion, log):
        raise MotionError("the pose is out of reach")


def test_an_aborted_grasp_reports_the_lift_height_asked_for():
    world = SimpleNamespace(
        object=SimpleNamespace(T_world_object=lambda: np.eye(4)),
        hand=SimpleNamespace(contacts=lambda: []),
    )
    held = HeldTest(lift_height=0.03)
    outcome = run_policy(world, None, _Unreachable(), None, held)  # type: ignore[arg-type]
    assert outcome.aborted and outcome.held is None and not outcome.success
    assert outcome.lift_height == 0.03
    assert outcome_json(outcome)["lift_height"] == 0.03
    assert outcome_json(outcome)["held_after_lift"] is False


def test_the_benchmark_held_test_judges_robot_and_human_with_gravity_off(tmp_path, monkeypatch):
    """--held-test benchmark: the weight cancelled from the lift on, each push the whole
    weight for 2 s, the bounds 5 cm and 15 deg; result.json names the test, for the
    robot and the human reference alike."""
    from graspframe_sapien.drivers import SapienObjectProbe

    monkeypatch.setenv("GRASPFRAME_CACHE_DIR", str(tmp_path / "cache"))  # a fresh reference
    forces: list[object] = []
    original = SapienObjectProbe.apply_force

    def spy(self, f_world):
        forces.append(None if f_world is None else np.asarray(f_world, dtype=float))
        return original(self, f_world)

    monkeypatch.setattr(SapienObjectProbe, "apply_force", spy)
    request = RunRequest(
        hand="barrett",
        grasp=HumanGrasp.PINCH,
        mount="floating",
        out_root=str(tmp_path / "runs"),
        record=False,
        held_test_name="benchmark",
    )
    result = run_grasp(request, default_registry()).to_json()
    outcome = result["outcome"]
    assert outcome["held_test"] == "benchmark"
    assert result["score"]["human_held_test"]["held_test"] == "benchmark"
    assert "--held-test benchmark" in result["reproduce"]
    assert outcome["success"], outcome["failure_reason"]
    assert set(outcome["disturbance"]) == {"+x", "-x", "+y", "-y", "+z", "-z"}
    assert all(
        m["shift_mm"] <= 50.0 and m["turn_deg"] <= 15.0 for m in outcome["disturbance"].values()
    )
    grasped = default_registry().default_object_for(HumanGrasp.PINCH)
    weight = grasped.mass * 9.81
    # Per test (robot, then human): the weight cancelled, six pushes each back to the
    # cancelled weight, then nothing.
    up = np.array([0.0, 0.0, weight])
    pushes = [f for f in forces if f is not None and not np.allclose(f, up)]
    assert len(pushes) == 12
    for push in pushes[:6]:
        assert np.linalg.norm(push - up) == pytest.approx(weight)
    assert forces[-1] is None


def test_an_unknown_held_test_or_a_benchmark_with_its_own_push_is_refused():
    from graspframe.cli.commands import main

    with pytest.raises(
        InputError, match="unknown held test 'dexgrasp'; held tests: graspframe, benchmark"
    ):
        RunRequest(hand="barrett", grasp=HumanGrasp.PINCH, held_test_name="dexgrasp").held_test()
    with pytest.raises(InputError, match="pushes with the object's whole weight"):
        RunRequest(
            hand="barrett",
            grasp=HumanGrasp.PINCH,
            held_test_name="benchmark",
            disturbance_fraction=0.2,
        ).held_test()
    assert main(["evaluate", "--hands", "barrett", "--held-test", "dexgrasp"]) == 1


def test_the_benchmark_words_name_gravity_and_its_bounds():
    from graspframe.strategy.held_check import held_test_named, held_test_words

    words = held_test_words(held_test_named("benchmark"))
    assert "pushes of 100 % of its weight for 2 s each, gravity off" in words
    assert "within 50 mm and 15 deg" in words
