"""What `graspframe run` prints once a run is over: the classification, the plan, the
outcome (held after the lift and under the pushes), a joint the simulator moved past its
limit, the score and where the files are."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from rich.console import Console

if TYPE_CHECKING:  # the run's types import the whole pipeline: only for annotations here
    from graspframe.motion.joint_limits import LimitExcess
    from graspframe.run.result import Quality, RunResult


def _tested(value: bool | None, skipped: str | None) -> str:
    if value is not None:
        return str(value)
    return f"not tested ({skipped})" if skipped else "not tested"


def _excess_text(violation: LimitExcess) -> str:
    """A joint's excess past its limit: "12.3 deg" or "4.0 mm"."""
    return f"{violation.excess_shown:.1f} {violation.unit}"


def _quality_text(quality: Quality) -> str:
    if quality.error is not None:
        return f"not computed ({quality.error})"
    if quality.measured is None:
        return "- (no contacts)"
    return f"{quality.measured.epsilon_l1:.3f}"


def print_run_summary(result: RunResult, console: Console) -> None:
    """The run in a few lines on `console`: the human grasp, the plan, the grasp and its
    held test, the score, where the files are."""
    classification = result.human.classification if result.human else None
    if classification is not None:
        console.print(
            f"image: human {classification.grasp.value} "
            f"(confidence {classification.confidence:.2f}, {classification.classifier})"
        )
    if result.plan is not None:
        plan = result.plan.plan
        console.print(
            f"[bold]{plan.hand}[/bold]: human {plan.grasp.value} -> preshape {plan.preshape}, "
            f"{plan.approach} approach, {'volar' if plan.volar else 'non-volar'}"
        )
    outcome = result.outcome
    if outcome is not None:
        disturbance = _tested(outcome.held_under_disturbance, outcome.disturbance_skipped)
        console.print(
            f"corrections: {outcome.corrections}   palm contact: {outcome.palm_contact}   "
            f"held after a {1000 * outcome.lift_height:.0f} mm lift: {outcome.held_after_lift} "
            f"(object rose {round(1000 * outcome.object_rise)} mm)   "
            f"held under disturbance: {disturbance}   held test: {outcome.verdict.held_test}"
        )
        per_finger: dict[str, int] = {}
        for contact in outcome.contacts:
            per_finger[contact.real_finger] = per_finger.get(contact.real_finger, 0) + 1
        listing = ", ".join(f"{f} {n}" for f, n in sorted(per_finger.items())) or "none"
        console.print(f"contacts per real finger: {listing}")
        if outcome.failure_reason:
            console.print(f"[yellow]grasp failed:[/yellow] {outcome.failure_reason}")
    if result.execution is not None and result.execution.joint_limits.violations:
        violations = result.execution.joint_limits.violations
        others = f" (and {len(violations) - 1} more joints)" if len(violations) > 1 else ""
        console.print(
            f"[yellow]the simulator broke a joint limit:[/yellow] {violations[0].describe()}"
            f"{others}; see joint_limits in result.json"
        )
    score = result.score
    if score is not None:
        if score.comparison is not None:
            comparison = score.comparison
            console.print(
                f"virtual fingers robot {comparison.robot_count} / human "
                f"{comparison.human_count}: position error {comparison.position_err_mm:.1f} mm, "
                f"orientation error {comparison.orientation_err_deg:.1f} deg"
            )
        elif score.error is not None:
            console.print(f"virtual fingers: not scored ({score.error})")
        if score.human_held is not None and not score.human_held.held:
            console.print(
                f"[yellow]the human reference does not hold:[/yellow] "
                f"{score.human_held.failure} (scored against it all the same)"
            )
        for violation in score.human_joint_limit_violations:
            console.print(
                f"[yellow]the simulator broke a joint limit of the human reference:[/yellow] "
                f"{violation.joint} past it by {_excess_text(violation)}"
            )
        console.print(
            "grasp quality (Ferrari-Canny epsilon, L1): "
            f"robot {_quality_text(score.quality_robot)}, "
            f"human {_quality_text(score.quality_human)}"
        )
    console.print(f"result: {result.result_path}")
    if result.snapshots is not None:
        console.print(f"pictures: {result.snapshots}")
    if result.human_reference_picture is not None:
        console.print(f"human reference: {result.human_reference_picture}")
    if result.servo is not None:
        moved_mm = sum(math.hypot(*step.correction_mm) for step in result.servo.steps)
        console.print(
            f"servo: {len(result.servo.steps)} measurements, the hand moved {moved_mm:.0f} mm "
            f"in all: {result.servo.picture}"
        )
    recording = result.artifacts.get("recording")
    if recording:
        console.print(f"recording: {recording}  (graspframe review {recording})")
