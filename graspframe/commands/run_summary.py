"""What `graspframe run` prints once a run is over: the classification, the plan, the
outcome (held after the lift and under the pushes), the score and where the files are."""

from __future__ import annotations

from rich.console import Console


def _tested(value: bool | None) -> str:
    return "not tested" if value is None else str(value)


def _quality_text(quality: dict | None) -> str:
    if not quality:
        return "- (no contacts)"
    if "error" in quality:
        return f"not computed ({quality['error']})"
    return f"{quality['epsilon_l1']:.3f}"


def print_run_summary(result: dict, console: Console) -> None:
    """The summary of one run's result dictionary (result.json), on `console`."""
    from graspframe.strategy.held_test import LIFT_HEIGHT

    plan, outcome, score = result["plan"], result["outcome"], result.get("score", {})
    classification = result.get("classification")
    if classification:
        console.print(
            f"image: human {classification['grasp']} "
            f"(confidence {classification['confidence']:.2f}, {classification['classifier']})"
        )
    console.print(
        f"[bold]{plan['hand']}[/bold]: human {plan['grasp']} -> preshape {plan['preshape']}, "
        f"{plan['approach']} approach, {'volar' if plan['volar'] else 'non-volar'}"
    )
    console.print(
        f"corrections: {outcome['corrections']}   palm contact: {outcome['palm_contact']}   "
        f"held after a {100 * LIFT_HEIGHT:.0f} cm lift: {outcome['held_after_lift']} "
        f"(object rose {1000 * outcome['object_rise']:.0f} mm)   "
        f"held under disturbance: {_tested(outcome['held_under_disturbance'])}"
    )
    per_finger: dict[str, int] = {}
    for contact in outcome["contacts_world"]:
        per_finger[contact["real_finger"]] = per_finger.get(contact["real_finger"], 0) + 1
    listing = ", ".join(f"{f} {n}" for f, n in sorted(per_finger.items())) or "none"
    console.print(f"contacts per real finger: {listing}")
    if outcome["failure_reason"]:
        console.print(f"[yellow]grasp failed:[/yellow] {outcome['failure_reason']}")
    comparison = score.get("comparison")
    if comparison:
        robot_n, human_n = comparison["robot_count"], comparison["human_count"]
        console.print(
            f"virtual fingers robot {robot_n} / human {human_n}: "
            f"position error {comparison['position_err_mm']:.1f} mm, "
            f"orientation error {comparison['orientation_err_deg']:.1f} deg"
        )
    elif "error" in score:
        console.print(f"virtual fingers: not scored ({score['error']})")
    human_held = score.get("human_held_test")
    if human_held and not human_held["held"]:
        console.print(
            f"[yellow]the human reference does not hold:[/yellow] {human_held['failure']} "
            "(scored against it all the same)"
        )
    quality = score.get("quality") or {}
    if quality:
        console.print(
            "grasp quality (Ferrari-Canny epsilon, L1): "
            + ", ".join(f"{who} {_quality_text(q)}" for who, q in quality.items())
        )
    console.print(f"result: {result['result_path']}")
    if result.get("snapshots"):
        console.print(f"pictures: {result['snapshots']}")
    if result.get("human_reference_picture"):
        console.print(f"human reference: {result['human_reference_picture']}")
    if result.get("recording"):
        console.print(
            f"recording: {result['recording']}  (graspframe review {result['recording']})"
        )
