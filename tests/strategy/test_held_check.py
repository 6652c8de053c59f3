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
