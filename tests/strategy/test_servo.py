"""The servo strategy on the arm in SAPIEN, with the simulated depth camera: it corrects
an object 5 cm from where the robot believes it, holds where the method misses, leaves a
correct belief alone, and reports every measurement (events, result.json, servo.png)."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import HumanGrasp
from graspframe.experiments.trials import TrialSpec
from graspframe.perception.localise import ObjectFit
from graspframe.perception.servo_step import ServoStep
from graspframe.plugin_system import events
from graspframe.run.request import RunRequest
from graspframe.run.runner import run_grasp
from graspframe.strategy.servo import STANDOFF_SKIPPED, ServoParams

ERROR = (0.05, 0.0)  # [m] the object 5 cm from the belief along -x of the belief


def _run(tmp_path, strategy: str, error=ERROR):
    request = RunRequest(
        hand="barrett",
        grasp=HumanGrasp.PINCH,
        object_error=error,
        strategy=strategy,
        record=False,
        out_root=str(tmp_path),
    )
    return run_grasp(request)


def test_the_servo_holds_a_pinch_the_method_misses(tmp_path):
    method = _run(tmp_path, "method")
    assert method.outcome is not None and not method.outcome.success
    servo = _run(tmp_path, "servo")
    assert servo.outcome is not None and servo.outcome.success, servo.outcome.failure_reason
    assert servo.servo is not None
    first = servo.servo.steps[0]
    assert first.stage == "start" and first.fit.accepted
    # The first look, before the arm moves, shifts the path by the error.
    assert np.allclose(first.correction_mm, [-50.0, 0.0], atol=3.0)
    # Then every later measurement agrees within the tolerance, and nothing moves again.
    tolerance_mm = 1000 * ServoParams().tolerance
    assert all(1000 * np.hypot(*step.fit.shift_xy) < tolerance_mm for step in servo.servo.steps[1:])
    stages = {step.stage for step in servo.servo.steps}
    assert stages == {"start", "via", "pre-approach", "standoff"}
    saved = json.loads(servo.result_path.read_text())
    steps_json = [step.to_json() for step in servo.servo.steps]
    assert saved["servo"]["steps"] == json.loads(json.dumps(steps_json))
    kinds = [event["kind"] for event in saved["events"]]
    assert kinds.count("execute.servo") == len(servo.servo.steps)
    # Each event's payload is made from its step.
    servo_events = [event for event in saved["events"] if event["kind"] == "execute.servo"]
    payloads = [{k: v for k, v in e.items() if k not in ("kind", "sim_time")} for e in servo_events]
    assert payloads == saved["servo"]["steps"]
    assert "execute.depth_image" not in kinds  # for observers only: the recording
    picture = servo.servo.picture
    assert picture.is_file() and picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_belief_that_is_right_is_left_alone(tmp_path):
    servo = _run(tmp_path, "servo", error=(0.0, 0.0))
    assert servo.outcome is not None and servo.outcome.success
    assert servo.servo is not None
    assert all(step.correction_mm == (0.0, 0.0) for step in servo.servo.steps)
    assert all(1000 * np.hypot(*s.fit.shift_xy) < 3.0 for s in servo.servo.steps if s.fit.accepted)


def test_a_volar_grasp_keeps_the_method_loop(tmp_path):
    request = RunRequest(
        hand="barrett",
        grasp=HumanGrasp.LARGE_DIAMETER,
        strategy="servo",
        record=False,
        out_root=str(tmp_path),
    )
    result = run_grasp(request)
    assert result.outcome is not None and result.outcome.success
    assert result.servo is None  # no camera measurement: the palm sensor corrects


@pytest.mark.parametrize(
    ("strategy", "noise", "trial_id"),
    [
        ("method", 1.0, "arm/barrett/pinch/B0"),
        ("servo", 1.0, "arm/barrett/pinch/B0/servo"),
        ("servo", 2.0, "arm/barrett/pinch/B0/servo-noise2"),
    ],
)
def test_a_servo_trial_has_an_id_of_its_own(strategy, noise, trial_id):
    spec = TrialSpec(
        "barrett", "pinch", "B0", ERROR, 0, "runs", strategy=strategy, camera_noise=noise
    )
    assert spec.trial_id == trial_id


def test_a_correction_too_large_for_the_standoff_is_reported_as_skipped():
    """The step the strategy records when it refuses a sideways move at the standoff, and
    the event payload made from it."""
    fit = ObjectFit(np.eye(4), (0.03, 0.0), 500, 0.9, 1.0, True, None)
    step = ServoStep("standoff", 1, fit, (0.0, 0.0), skipped=STANDOFF_SKIPPED)
    record = step.to_json()
    assert record["skipped"] == "larger than the standoff allows"
    assert "skipped" not in replace(step, skipped=None).to_json()  # only when set
    events.EXECUTE_SERVO.check(record)  # a declared, optional field
    with pytest.raises(GraspframeError, match="undeclared payload fields"):
        events.EXECUTE_SERVO.check({**record, "reason": "x"})
