"""The checks of `graspframe check-hand` (graspframe/cli/check_hand.py): what each
checked, its verdict and what it measured.

Five checks, in order, each reported with its verdict and what it measured:

1. the description and its model (`graspframe.checks.contracts.hand_problems`: joints and limits
   against the model, real fingers, couplings, preshapes within limits, the mapping of
   all six grasps, the palm frame's +z pointing out of the palm) and, once those hold,
   no links overlapping in a preshape's open posture
   (`self_collision.self_collision_problems`, failed here as in the contract test); when
   it fails, each preshape is still drawn posed closed around its design object (no
   physics) where the model loads, to see what is wrong (a palm frame turned over shows
   at once);
2. closing each preshape in free space brings its opposed fingers together
   (`grasp_checks.closing_gaps`): the gap of every pair, open and closed; and a picture
   of each preshape closed kinematically around its design object (every finger stops
   where it first touches it: `hand_geometry.closing_configurations`), with those gaps
   in its caption, to see where the fingers land before any physics runs;
3. with an arm, the hand mounted on it (bolted straight on and through each mounting)
   has no link inside an arm link (`mounting.mount_overlaps`): the deepest touch of
   each mount, and every pair deeper than the tolerance as a problem;
4. unless asked not to, the hand alone (on the floating base, no arm) holds each
   preshape's design object through the lift and the pushes of a real run, in the
   registered physics backend (`grasp_checks.hold_trials`): every raise of the goal
   off the table, contacts per real finger, the object's motion in the hand and, for a
   failed hold, what limited it (`grasp_checks.hold_limit`: the fingers that never
   touched, the squeeze times the friction against the weight); a picture of every
   trial, held or not, is written to the pictures folder (a trial that recorded no
   moment, no plan found or its approach aborted: its preshape posed around the design
   object, the reason in the title);
5. with experiment A's objects, the same for every human grasp on its own object, the
   palm placed as the human reference places it: every grasp a preshape serves, not
   only the one its design object stands for.

A check runs only when the ones before it passed (a hand whose model does not load
cannot be closed). Every picture of a preshape is `NAME_closing.png`, of a trial
`PRESHAPE_GRASP.png` (`PRESHAPE_GRASP_experiment_a.png` on experiment A's object). The
grasp checks are for robot hands: the human reference hand's postures are checked by the
reference procedure (graspframe/strategy/human_reference.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from graspframe.checks.contracts import hand_problems
from graspframe.checks.grasps import (
    OPPOSED_MAX_GAP,
    ExperimentObjects,
    HoldTrial,
    closing_gaps,
    closing_problems,
    hold_limit,
    hold_measures,
    hold_trials,
)
from graspframe.checks.self_collision import open_preshape_collisions, self_collision_problems
from graspframe.common.files import make_folder
from graspframe.common.grasps import HUMAN_HAND
from graspframe.hal.descriptions import ArmDescription, HandDescription, HandPreshape, JointSpec
from graspframe.hal.drivers import Backend
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.strategy.held_check import HeldTest, held_test_words


@dataclass
class CheckResult:
    """One check: what it checks, the problems found (none: passed), what it measured,
    and why it did not run (skipped)."""

    name: str
    problems: list[str] = field(default_factory=list)
    measured: list[str] = field(default_factory=list)
    skipped: str | None = None

    @property
    def passed(self) -> bool:
        return self.skipped is None and not self.problems

    def lines(self, number: int) -> list[str]:
        if self.skipped is not None:
            return [f"{number}. {self.name}: not run ({self.skipped})"]
        count = len(self.problems)
        verdict = (
            "passed" if self.passed else f"FAILED ({count} problem{'s' if count != 1 else ''})"
        )
        lines = [f"{number}. {self.name}: {verdict}"]
        lines += [f"     {line}" for line in self.measured]
        lines += [f"     problem: {problem}" for problem in self.problems]
        return lines


def _limits(joint: JointSpec) -> str:
    return f"{joint.name} [{joint.lower:.4g}, {joint.upper:.4g}]"


def hand_summary(hand: HandDescription) -> list[str]:
    """A few lines saying what the hand is: joints, real fingers, preshapes, mapping."""
    mapping = ", ".join(f"{g.value} -> {p}" for g, p in hand.grasp_map.items())
    fingers = ", ".join(
        f"{f} ({len(links)} link{'s' if len(links) != 1 else ''})"
        for f, links in hand.real_fingers.items()
    )
    return [
        f"model: {hand.model_path}",
        f"joints ({len(hand.joints)}): {', '.join(_limits(j) for j in hand.joints)}",
        f"real fingers ({len(hand.real_fingers)}): {fingers}",
        f"palm frame: {hand.palm_frame}; palm sensor: {hand.palm_sensor_link}",
        f"preshapes ({len(hand.preshapes)}): {', '.join(hand.preshapes)}",
        f"mapping: {mapping}",
    ]


def _description_check(hand: HandDescription) -> CheckResult:
    problems = hand_problems(hand)
    # The open postures are checked for self-collision once the description holds
    # together; an overlap fails the check as it fails the contract test
    # (`assert_hand_free_of_self_collision`): a posture whose links interpenetrate cannot
    # be built, even though the simulator, which runs without self-collision, would go on.
    measured = hand_summary(hand)
    if not problems:
        collisions = open_preshape_collisions(hand, CollisionModel(model_of(hand)))
        clear = [name for name, pairs in collisions.items() if not pairs]
        measured.append(f"open preshapes free of self-collision: {', '.join(clear) or 'none'}")
        problems = self_collision_problems(hand)
    return CheckResult(
        "the description against its model (joints, limits, real fingers, couplings, "
        "preshapes, the mapping, the palm frame's +z out of the palm, no self-collision in "
        "an open preshape)",
        problems=problems,
        measured=measured,
    )


def _closing_check(hand: HandDescription, pictures: Path | None) -> CheckResult:
    result = CheckResult(
        f"closing in free space brings opposed fingers within {1000 * OPPOSED_MAX_GAP:.0f} mm",
        problems=closing_problems(hand),
    )
    for preshape in hand.preshapes.values():
        gaps = ", ".join(
            f"{a}-{b} {round(1000 * g.open_gap)} -> {round(1000 * g.closed_gap)} mm"
            for g in closing_gaps(hand, preshape)
            for a, b in [g.fingers]
        )
        result.measured.append(f"{preshape.name}: {gaps}")
        if pictures is not None and preshape.design_object is not None:
            caption = (
                f"{hand.name} {preshape.name}: closed around its design object without "
                "physics (each finger stops where it first touches it)\n"
                f"fingertip gaps closing in free space (no object), open -> closed: {gaps}"
            )
            path = _draw_closing(pictures / f"{preshape.name}_closing.png", hand, preshape, caption)
            result.measured.append(f"  picture: {path}")
    return result


def _draw_closing(path: Path, hand: HandDescription, preshape: HandPreshape, caption: str) -> Path:
    """The preshape closed kinematically around its design object, in the palm frame, to
    `path`, captioned `caption`."""
    import numpy as np

    from graspframe.checks.grasps import design_object
    from graspframe.common.transforms import inv_T, make_T
    from graspframe.pictures.hand_grasp import draw_hand_grasp
    from graspframe.strategy.hand_geometry import closing_configurations
    from graspframe.strategy.reference_poses import R_object_palm_for_design

    assert preshape.design_object is not None
    obj = design_object(preshape)
    R_object_palm = R_object_palm_for_design(preshape.design_object)
    T_palm_object = inv_T(
        make_T(R_object_palm, -R_object_palm @ np.asarray(preshape.grasp_center_palm))
    )
    closed = closing_configurations(hand, preshape, obj, T_palm_object)[-1]
    make_folder(path.parent, "pictures folder")
    return draw_hand_grasp(path, hand, closed, obj, T_palm_object, np.zeros((0, 3)), [], caption)


def _posed_pictures(hand: HandDescription, folder: Path) -> list[str]:
    """For a description that failed its check: each preshape still drawn closed around
    its design object (posed, no physics; nothing else can run) to see what is wrong, or
    why it cannot be drawn: one line each, or one line when the model does not load."""
    from graspframe.common.errors import GraspframeError

    try:
        model_of(hand)
    except GraspframeError as exc:
        return [f"no pictures: the model does not load ({exc})"]
    lines = []
    for name, preshape in hand.preshapes.items():
        if preshape.design_object is None:
            lines.append(f"{name}: no picture (it declares no design object)")
            continue
        caption = (
            f"{hand.name} {name}: posed closed around its design object, without physics; "
            "the description check failed (see its problems)\n"
            "the palm +z (red arrow) must point out of the palm, at the object"
        )
        try:
            path = _draw_closing(folder / f"{name}_closing.png", hand, preshape, caption)
        except (GraspframeError, KeyError, ValueError) as exc:
            lines.append(f"{name}: no picture, it cannot be posed ({exc})")
        else:
            lines.append(
                f"{name}: posed closed around its design object (no physics), picture: {path}"
            )
    return lines


def _hold_checks(
    hand: HandDescription,
    backend: Backend,
    pictures: Path | None,
    progress: Callable,
    experiment: ExperimentObjects | None,
    held: HeldTest,
) -> list[CheckResult]:
    """The hold check on the design objects and, with `experiment`, the one on
    experiment A's objects (every grasp each preshape serves), judged by `held`."""
    design = CheckResult(
        f"the hand alone holds each preshape's design object ({backend.name} physics: "
        f"approach, close, {held_test_words(held)})"
    )
    missing = [name for name, p in hand.preshapes.items() if p.design_object is None]
    design.problems += [f"preshape {name!r} declares no design object" for name in missing]
    trials = hold_trials(hand, backend, progress=progress, keep_unplanned=True,
                         experiment=experiment, held=held)  # fmt: skip
    results = [design]
    if experiment is not None:
        results.append(
            CheckResult(
                "the hand alone holds experiment A's object for every human grasp (each "
                "grasp a preshape serves, the palm placed as the human reference places it)"
            )
        )
    for kind, result in zip((False, True), results, strict=False):
        chosen = [trial for trial in trials if trial.experiment == kind]
        result.measured.append(f"{sum(t.held for t in chosen)} of {len(chosen)} held")
        for trial in chosen:
            _report_trial(result, hand, trial, pictures)
    return results


def _report_trial(
    result: CheckResult, hand: HandDescription, trial: HoldTrial, pictures: Path | None
) -> None:
    result.measured.append(_trial_title(trial))
    result.measured += [f"  {line}" for line in _plan_lines(trial)]
    result.measured += [f"  {line}" for line in hold_measures(trial)]
    if pictures is not None and trial.moments:
        path = _draw_trial(pictures, hand, trial)
        result.measured.append(f"  picture: {path}")
    elif pictures is not None:
        path = _draw_posed_trial(pictures, hand, trial)
        result.measured.append(f"  picture (posed, nothing was recorded): {path}")
    if not trial.held:
        result.problems.append(
            f"preshape {trial.preshape!r} ({trial.grasp.value}, {trial.obj.name}): "
            f"{trial.outcome.failure_reason}; limited by: {hold_limit(trial)}"
        )


def _plan_lines(trial: HoldTrial) -> list[str]:
    """How the plan kept the hand off the table: every raise, and what it cost."""
    if trial.checked is None:
        return []
    plan = trial.checked.plan
    lines = []
    if plan.table_raise > 0.0005:
        lines.append(
            f"goal raised {1000 * plan.table_raise:.0f} mm to keep the hand off the table "
            f"(lowest: link {plan.lowest_link!r}, {1000 * plan.lowest_below_palm:.0f} mm "
            "below the palm)"
        )
    if plan.reach:
        lines.append(
            f"the raise lifted the fingers off the object; planned instead with {plan.reach}"
        )
    if plan.table_raise > 0.0005 or plan.reach:
        fingers = ", ".join(plan.fingers_on_object) or "none"
        lines.append(
            f"real fingers on the object, closed without physics: {fingers} (the lowest "
            f"first touch {1000 * plan.lowest_touch_height:.0f} mm above its centroid)"
        )
    return lines


def _mount_check(hand: HandDescription, arm: ArmDescription) -> CheckResult:
    from graspframe.common.errors import GraspframeError
    from graspframe.robot_models.mounting import MOUNT_OVERLAP_TOLERANCE, mount, mount_overlaps

    result = CheckResult(
        f"mounted on {arm.name}: no hand link inside an arm link (at most "
        f"{1000 * MOUNT_OVERLAP_TOLERANCE:.0f} mm; bolted straight on or through a "
        "mounting, the arm at home, every preshape open and closed)"
    )
    # The mounts are alternatives (robot_models/mounting.py's check_mounts): one that
    # overlaps is not used, a problem only when every mount overlaps.
    overlapping: list[str] = []
    usable = 0
    for mounting in (None, *hand.mountings):
        how = "bolted straight on" if mounting is None else f"through its {mounting} mounting"
        try:
            robot = mount(arm, hand, mounting=mounting, check=False)
        except GraspframeError as exc:
            result.problems.append(f"{how}: {exc}")
            continue
        touching = mount_overlaps(robot, tolerance=-1.0)
        deepest = (
            f"deepest: {touching[0].describe()}" if touching else "no hand link touches the arm"
        )
        overlaps = [f"{how}: {overlap.describe()}" for overlap in mount_overlaps(robot)]
        result.measured.append(f"{how}: {deepest}" + ("; not used" if overlaps else ""))
        overlapping += overlaps
        usable += not overlaps
    if not usable:
        result.problems += overlapping
    return result


def _trial_title(trial: HoldTrial) -> str:
    use = "volar" if trial.grasp.volar_for_robot else "non-volar"
    size = ", ".join(f"{k} {1000 * v:.0f} mm" for k, v in trial.obj.dimensions.items())
    what = f"{trial.obj.name}, " if trial.experiment else ""
    verdict = "held" if trial.held else f"NOT HELD: {trial.outcome.failure_reason}"
    return (
        f"{trial.preshape} ({trial.grasp.value}, {use}; {what}{trial.obj.shape} {size}, "
        f"{1000 * trial.obj.mass:.0f} g): {verdict}"
    )


def _draw_trial(folder: Path, hand: HandDescription, trial: HoldTrial) -> Path:
    from graspframe.pictures.snapshots import draw_grasp

    assert trial.checked is not None  # a trial with moments ran a plan
    on = f"experiment A's {trial.obj.name}" if trial.experiment else "its design object"
    what = f"{hand.name} alone, {trial.preshape} ({trial.grasp.value}) on {on}"
    make_folder(folder, "pictures folder")
    path = folder / _trial_picture(trial)
    return draw_grasp(
        path, trial.checked.robot, trial.checked.T_world_base, trial.obj, 0.0, trial.moments,
        what, trial.held, trial.outcome.failure_reason,
    )  # fmt: skip


def _draw_posed_trial(folder: Path, hand: HandDescription, trial: HoldTrial) -> Path:
    """A trial that recorded no moment (no plan, or its approach aborted): its preshape
    posed closed around the design object, the reason in the title."""
    caption = (
        f"{hand.name} alone, {trial.preshape} ({trial.grasp.value}) on its design object; "
        f"not held: {trial.outcome.failure_reason}\nno moment of the trial was recorded: "
        "the preshape posed closed around its design object, without physics"
    )
    path = folder / _trial_picture(trial)
    return _draw_closing(path, hand, hand.preshape(trial.preshape), caption)


def _trial_picture(trial: HoldTrial) -> str:
    """PRESHAPE_GRASP.png, PRESHAPE_GRASP_experiment_a.png for experiment A's object."""
    suffix = "_experiment_a" if trial.experiment else ""
    return f"{trial.preshape}_{trial.grasp.value}{suffix}.png"


def check_hand_report(
    hand: HandDescription,
    backend: Backend | None = None,
    pictures: Path | None = None,
    progress: Callable[[str], None] = lambda _message: None,
    arm: ArmDescription | None = None,
    experiment: ExperimentObjects | None = None,
    held: HeldTest | None = None,
) -> tuple[bool, list[str]]:
    """(passed, lines to print) for one hand description; with a backend, the hand
    alone must also hold its design objects in it and, with `experiment`, experiment
    A's object for every human grasp (pictures of each trial go to the `pictures`
    folder when one is given); with an arm, its links must clear the arm's once
    mounted. held: the held test of the hold checks (default: graspframe's)."""
    held = held or HeldTest()
    checks = [_description_check(hand)]
    robot_hand = hand.name != HUMAN_HAND
    if robot_hand and pictures is not None and not checks[0].passed:
        checks[0].measured += _posed_pictures(hand, pictures)
    reason = "the human hand's postures are checked by the reference procedure"
    if not checks[-1].passed:
        reason = "the description check failed"
    checks.append(_closing_check(hand, pictures) if robot_hand and checks[-1].passed else
                  CheckResult("closing in free space", skipped=reason))  # fmt: skip
    if arm is not None:
        checks.append(
            _mount_check(hand, arm) if robot_hand and checks[0].passed else
            CheckResult(f"mounted on {arm.name}", skipped=reason)
        )  # fmt: skip
    holds = ["holding the design objects"]
    if experiment is not None:
        holds.append("holding experiment A's objects")
    if backend is None:
        checks += [CheckResult(name, skipped="--no-hold") for name in holds]
    elif robot_hand and checks[1].passed:
        checks += _hold_checks(hand, backend, pictures, progress, experiment, held)
    else:
        skipped = reason if not robot_hand or not checks[0].passed else "closing failed"
        checks += [CheckResult(name, skipped=skipped) for name in holds]
    passed = all(check.passed or check.skipped for check in checks)
    ran = sum(check.skipped is None for check in checks)
    verdict = "all passed" if passed else "FAILED"
    lines = [f"hand {hand.name}: {ran} of {len(checks)} checks ran, {verdict}"]
    for number, check in enumerate(checks, start=1):
        lines += check.lines(number)
    return passed, lines
