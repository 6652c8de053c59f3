"""Model-level grasp checks of a hand: does its model close and hold at all?

Two checks every hand gets (built-in or third-party; `graspframe check-hand` runs them):

- `closing_problems`: closing each preshape in free space brings the fingertips (the
  last shaped link of each finger; the palm's pad) of each declared pair
  (`HandPreshape.opposed`) within OPPOSED_MAX_GAP, nearer than they started; with no
  pair declared, some pair that starts OPEN_MIN_GAP apart (not neighbours) must end
  within OPPOSED_MAX_GAP. Shapes placed by Pinocchio, distances by coal.
- `hold_problems`: the hand alone, on the floating base (no arm), encloses and holds
  each preshape's design object: it is planned, approached, closed, lifted 5 cm and
  pushed exactly as a run does (`held` in docs/method.md), in a physics backend.
  `hold_trials` keeps each trial, `hold_measures` and `hold_limit` report it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from graspframe.common.defaults import DISTURBANCE_FRACTION
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.common.transforms import make_T
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.drivers import Backend, WorldConfig
from graspframe.hal.objects import ObjectDescription
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.strategy.held_check import GRAVITY, HeldTest
from graspframe.strategy.reference_poses import R_object_palm_for_design

if TYPE_CHECKING:  # method.py imports the planner, which imports this package's users
    from graspframe.strategy.arm_path import CheckedPlan
    from graspframe.strategy.execution import GraspOutcome, Moment

OPPOSED_MAX_GAP = 0.015  # [m] largest gap left between opposing fingers, closed in free space
OPEN_MIN_GAP = 0.03  # [m] an undeclared pair counts as opposing only from this far apart
# [kg/m^3] of a design object: the default objects are 400-1400 kg/m^3. At 500 the 29 g
# design handle of the Karlsruhe wrap was pushed out of the hand by its 0.14 N
# disturbance after the guarded approach; at 800 every built-in hand holds its own.
DESIGN_DENSITY = 800.0
DESIGN_FRICTION = (0.8, 0.6)  # static, dynamic: the default objects' (rubber/matt plastic)


def _finger_distance(
    model: CollisionModel, links_a: Iterable[str], links_b: Iterable[str]
) -> float:
    """[m] smallest distance between any shape of links_a and any shape of links_b."""
    import coal

    placed = list(model.shapes())
    best = math.inf
    for link_a, shape_a, T_a in placed:
        if link_a not in links_a:
            continue
        for link_b, shape_b, T_b in placed:
            if link_b not in links_b:
                continue
            request, result = coal.DistanceRequest(), coal.DistanceResult()
            distance = coal.distance(
                shape_a,
                coal.Transform3s(T_a[:3, :3], T_a[:3, 3]),
                shape_b,
                coal.Transform3s(T_b[:3, :3], T_b[:3, 3]),
                request,
                result,
            )
            best = min(best, float(distance))
    return best


def _tip_links(hand: HandDescription, model: CollisionModel, finger: str) -> set[str]:
    """The fingertip of a real finger: its shaped link furthest down the kinematic chain
    (the palm: its sensor pad). Fingers meet at their tips; their first links always sit
    beside each other and beside the palm."""
    if finger == PALM:
        return {hand.palm_sensor_link}
    shaped = {link for link, _shape, _T in model.shapes()}
    links = [link for link in hand.real_fingers[finger] if link in shaped]
    if not links:
        return set()

    def depth(link: str) -> int:
        n, parent = 0, model.parent_link(link)
        while parent is not None:
            n, parent = n + 1, model.parent_link(parent)
        return n

    deepest = max(depth(link) for link in links)
    return {link for link in links if depth(link) == deepest}


@dataclass(frozen=True)
class FingerGap:
    """Gap [m] between two real fingers in the open and the closed preshape."""

    fingers: tuple[str, str]
    open_gap: float
    closed_gap: float


def closing_gaps(hand: HandDescription, preshape: HandPreshape) -> list[FingerGap]:
    """Gaps of the preshape's opposed pairs (or of every pair of real fingers when it
    declares none), open and closed in free space."""
    model = CollisionModel(model_of(hand))
    fingers = list(hand.real_fingers)  # the palm opposes the fingers of a power grasp
    pairs = list(preshape.opposed) or list(itertools.combinations(fingers, 2))
    gaps = {}
    for label, q in (("open", preshape.open_q), ("closed", preshape.closed_q)):
        model.place(hand.with_model_followers(dict(q)))
        for a, b in pairs:
            gaps[(a, b, label)] = _finger_distance(
                model, _tip_links(hand, model, a), _tip_links(hand, model, b)
            )
    return [FingerGap((a, b), gaps[(a, b, "open")], gaps[(a, b, "closed")]) for a, b in pairs]


def closing_problems(hand: HandDescription) -> list[str]:
    """Preshapes whose fingers do not come together when closed in free space."""
    problems = []
    for preshape in hand.preshapes.values():
        gaps = closing_gaps(hand, preshape)
        if preshape.opposed:
            bad = [g for g in gaps if not _closes(g)]
        else:  # no declaration: a pair that starts apart must close
            apart = [g for g in gaps if g.open_gap >= OPEN_MIN_GAP] or gaps
            bad = [] if any(_closes(g) for g in apart) else [min(apart, key=lambda g: g.closed_gap)]
        for gap in bad:
            problems.append(
                f"preshape '{preshape.name}': closing in free space leaves {gap.fingers[0]} and "
                f"{gap.fingers[1]} {1000 * gap.closed_gap:.0f} mm apart (open: "
                f"{1000 * gap.open_gap:.0f} mm); opposing fingers must end within "
                f"{1000 * OPPOSED_MAX_GAP:.0f} mm"
            )
    return problems


def _closes(gap: FingerGap) -> bool:
    return gap.closed_gap <= OPPOSED_MAX_GAP and gap.closed_gap < gap.open_gap


def design_object(preshape: HandPreshape, scale: float = 1.0) -> ObjectDescription:
    """The preshape's design object as an object description (scaled in every
    dimension), standing on the table with its axis up."""
    design = preshape.design_object
    if design is None:
        raise ValueError(f"preshape {preshape.name!r} declares no design object")
    if design.shape == "cylinder":
        dimensions = {"radius": scale * design.radius, "length": scale * (design.length or 0.0)}
    else:
        dimensions = {"radius": scale * design.radius}
    probe = ObjectDescription(f"{preshape.name}_design", design.shape, dimensions, mass=1.0)
    return ObjectDescription(
        name=probe.name,
        shape=design.shape,
        dimensions=dimensions,
        mass=DESIGN_DENSITY * probe.volume,
        static_friction=DESIGN_FRICTION[0],
        dynamic_friction=DESIGN_FRICTION[1],
    )


def hand_alone_grasp(
    hand: HandDescription,
    grasp: HumanGrasp,
    backend: Backend,
    obj: ObjectDescription | None = None,
    disturb: bool = True,
    T_object_palm: NDArray[np.float64] | None = None,
    held: HeldTest | None = None,
) -> GraspOutcome:
    """The GraspOutcome of `_hand_alone` (the hand alone on the floating base, on its
    design object or `obj`, standing on a table at z = 0)."""
    return _hand_alone(hand, grasp, backend, obj, disturb, T_object_palm, held)[0]


def _design_placement(preshape: HandPreshape) -> NDArray[np.float64]:
    """T_object_palm holding the preshape's design object where it lies in the palm."""
    assert preshape.design_object is not None
    R = R_object_palm_for_design(preshape.design_object)
    return make_T(R, -R @ np.asarray(preshape.grasp_center_palm))


@dataclass(frozen=True)
class HandAloneSetup:
    """A grasp of the hand alone on the floating base, planned and ready to execute:
    the checked plan, the world to build for it and the object (standing on a table at
    z = 0)."""

    checked: CheckedPlan
    config: WorldConfig
    obj: ObjectDescription


def hand_alone_setup(
    hand: HandDescription,
    grasp: HumanGrasp,
    obj: ObjectDescription | None = None,
    T_object_palm: NDArray[np.float64] | None = None,
    xy: tuple[float, float] = (0.0, 0.0),
) -> HandAloneSetup:
    """Plan `grasp` for the hand alone on the floating base, on its design object (or
    `obj`) standing on a table at z = 0 at world (x, y) = `xy` [m]; T_object_palm: the
    human palm on the object (default: the preshape's design object where it lies in the
    palm)."""
    from graspframe.strategy.arm_path import floating_plan
    from graspframe.strategy.planner import PlanningTarget

    preshape = hand.preshape_for(grasp)
    if T_object_palm is None:
        if preshape.design_object is None:
            raise ValueError(f"preshape {preshape.name!r} declares no design object")
        T_object_palm = _design_placement(preshape)
    obj = obj or design_object(preshape)
    T_world_object = obj.T_world_standing(xy)
    checked = floating_plan(PlanningTarget(grasp, T_object_palm, T_world_object, hand, obj))
    config = WorldConfig(
        hand=hand,
        object=obj,
        robot=checked.robot,
        T_world_arm_base=checked.T_world_base,
        T_world_object=T_world_object,
    )
    return HandAloneSetup(checked, config, obj)


def _hand_alone(
    hand: HandDescription,
    grasp: HumanGrasp,
    backend: Backend,
    obj: ObjectDescription | None = None,
    disturb: bool = True,
    T_object_palm: NDArray[np.float64] | None = None,
    held: HeldTest | None = None,
) -> tuple[GraspOutcome, tuple[Moment, ...], CheckedPlan]:
    """(the outcome, its moments, the CheckedPlan on the floating base); T_object_palm:
    the human palm on the object (default: the design object where it lies in the
    palm); held: the held test (default: graspframe's, pushes when `disturb`)."""
    from graspframe.strategy.execution import execute
    from graspframe.strategy.method import MethodStrategy

    setup = hand_alone_setup(hand, grasp, obj, T_object_palm)
    checked = setup.checked
    policy = MethodStrategy(checked.plan, hand, setup.obj, checked.executor_params)
    execution = execute(backend, setup.config, policy, held or HeldTest(disturb=disturb))
    return execution.outcome, execution.moments, checked


@dataclass(frozen=True)
class ExperimentObjects:
    """What experiment A grasps with the hand alone: `human`, the human hand whose
    postures place the palm on each object (the reference placement of a run with
    --grasp), and `objects`, each human grasp's object (its default object)."""

    human: HandDescription
    objects: Mapping[HumanGrasp, ObjectDescription]


@dataclass(frozen=True)
class HoldTrial:
    """The hand alone grasping a preshape's design object: what was grasped, the real
    fingers meant to touch it (its opposed pairs', else every finger), what happened
    (`outcome`), and for pictures its moments (`moments`) and
    the plan on the floating base it ran (`checked`: a CheckedPlan; None when no plan
    was found). experiment: the trial grasps experiment A's object for its human grasp,
    placed by the human reference, instead of the preshape's design object."""

    grasp: HumanGrasp
    preshape: str
    obj: ObjectDescription
    fingers: tuple[str, ...]
    outcome: GraspOutcome
    moments: tuple[Moment, ...]
    checked: CheckedPlan | None
    experiment: bool = False  # experiment A's object for the grasp, not the design object

    @property
    def held(self) -> bool:
        return self.outcome.success


def hold_trials(
    hand: HandDescription,
    backend: Backend,
    progress: Callable[[str], None] = lambda _message: None,
    keep_unplanned: bool = False,
    experiment: ExperimentObjects | None = None,
    held: HeldTest | None = None,
) -> list[HoldTrial]:
    """One hand-alone grasp of its design object per preshape and volar/non-volar use of
    it (in the order of the grasp map), then, with `experiment`, one per human grasp on
    its experiment A object (every grasp a preshape serves); `progress` hears of each
    trial as it starts.

    keep_unplanned: a grasp the planner finds no plan for is a trial that was not held
    (aborted, no moments, no plan) instead of the PlanningError it raises by default.
    held: the held test of every trial (default: graspframe's).
    """
    from graspframe.strategy.planner import PlanningError

    runs: list[tuple[HumanGrasp, ObjectDescription, NDArray[np.float64] | None]] = []
    tried = set()
    for grasp, preshape_name in hand.grasp_map.items():
        preshape = hand.preshape(preshape_name)
        key = (preshape_name, grasp.volar_for_robot)
        if key in tried or preshape.design_object is None:
            continue
        tried.add(key)
        runs.append((grasp, design_object(preshape), None))
    if experiment is not None:
        from graspframe.strategy.reference_poses import reference_placement

        for grasp in hand.grasp_map:
            obj = experiment.objects[grasp]
            human_palm = reference_placement(obj, experiment.human.preshape_for(grasp))
            runs.append((grasp, obj, human_palm.T_object_palm))
    trials = []
    for grasp, obj, T_object_palm in runs:
        preshape_name = hand.grasp_map[grasp]
        preshape = hand.preshape(preshape_name)
        on = "its design object" if T_object_palm is None else f"experiment A's {obj.name}"
        progress(f"{preshape_name} ({grasp.value}): the hand alone on {on}")
        try:
            outcome, moments, checked = _hand_alone(
                hand, grasp, backend, obj, T_object_palm=T_object_palm, held=held
            )
        except PlanningError as exc:
            if not keep_unplanned:
                raise
            outcome, moments, checked = _unplanned(obj, str(exc)), (), None
        fingers = {f for pair in preshape.opposed for f in pair} or set(hand.real_fingers)
        meant = tuple(f for f in hand.real_fingers if f in fingers and f != PALM)
        experiment_trial = T_object_palm is not None
        trial = HoldTrial(grasp, preshape_name, obj, meant, outcome, moments, checked)
        trials.append(replace(trial, experiment=experiment_trial))
    return trials


def _unplanned(obj: ObjectDescription, reason: str) -> GraspOutcome:
    """The outcome of a grasp that found no plan: aborted, the object where it stood."""
    from graspframe.strategy.execution import GraspOutcome, Grip

    return GraspOutcome(
        contacts=[],
        T_world_object_at_hold=obj.T_world_standing(),
        grip=Grip(),
        held=None,
        aborted=f"no plan: {reason}",
    )


def hold_measures(trial: HoldTrial) -> list[str]:
    """What a trial measured, in words: contacts per real finger at the hold, the
    object's motion in the hand during the lift and under the pushes, and, when it was
    not held, what limited it: the fingers that never touched and the squeeze."""
    outcome = trial.outcome
    counts: dict[str, int] = {}
    for contact in outcome.contacts:
        counts[contact.real_finger] = counts.get(contact.real_finger, 0) + 1
    listing = ", ".join(f"{finger} {n}" for finger, n in sorted(counts.items())) or "none"
    lines = [f"contacts per real finger at the hold: {listing}"]
    if outcome.lift_motion is not None:
        lines.append(
            f"lift: the object rose {round(1000 * outcome.object_rise)} mm of "
            f"{1000 * outcome.lift_height:.0f} mm and moved "
            f"{outcome.lift_motion.describe()} in the hand"
        )
    if outcome.disturbance:
        direction, motion = max(outcome.disturbance.items(), key=lambda item: item[1].shift)
        lines.append(
            f"pushes: the largest motion in the hand was {motion.describe()} ({direction})"
        )
    if trial.held or trial.outcome.aborted:  # an aborted trial: its reason says it all
        return lines
    return lines + _limits(trial)


def _limits(trial: HoldTrial) -> list[str]:
    """Why a hold may have failed: fingers that never touched, squeeze against weight."""
    lines = []
    missing = _never_touched(trial)
    if missing:
        lines.append(f"never touched the object: {', '.join(missing)}")
    squeeze, friction, weight = _grip(trial)
    lines.append(
        f"squeeze: {squeeze:.1f} N of normal force at the hold; with the object's friction "
        f"{friction:g} it holds at most {friction * squeeze:.1f} N against the "
        f"{weight:.1f} N weight (plus half of it when pushed)"
    )
    return lines


def _never_touched(trial: HoldTrial) -> list[str]:
    """The real fingers meant to touch the object that had no contact at the hold."""
    touching = {contact.real_finger for contact in trial.outcome.contacts}
    return [finger for finger in trial.fingers if finger not in touching]


def _grip(trial: HoldTrial) -> tuple[float, float, float]:
    """(squeeze [N]: the normal force of every contact at the hold, summed; the object's
    static friction; its weight [N])."""
    squeeze = sum(abs(float(np.dot(c.f, c.n))) for c in trial.outcome.contacts)
    return squeeze, trial.obj.static_friction, trial.obj.mass * GRAVITY


def hold_limit(trial: HoldTrial) -> str:
    """What limited a failed hold, in a few words: the fingers that never touched, and
    the friction of the squeeze when it is below the weight and the pushes (half the
    weight); else that neither did; for an aborted trial, that it stopped before the
    hold (its reason says why)."""
    if trial.outcome.aborted:
        return "the trial stopped before the hold"
    limits = []
    missing = _never_touched(trial)
    if missing:
        limits.append(f"{', '.join(missing)} never touched the object")
    squeeze, friction, weight = _grip(trial)
    pushed = (1.0 + DISTURBANCE_FRACTION) * weight  # the pushes come on top of the weight
    if friction * squeeze < pushed:
        limits.append(
            f"squeeze {squeeze:.1f} N x friction {friction:g} = {friction * squeeze:.1f} N, "
            f"below the {weight:.1f} N weight plus {100 * DISTURBANCE_FRACTION:.0f} % of it "
            "(the pushes)"
        )
    return "; ".join(limits) or (
        "neither the fingers (all touched) nor the squeeze (its friction exceeds the "
        "weight and the pushes): see the picture"
    )


def hold_problems(hand: HandDescription, backend: Backend) -> list[str]:
    """Preshapes whose design object the hand alone does not hold (one trial per
    preshape and volar/non-volar use of it)."""
    problems = [
        f"preshape {name!r} declares no design object to hold"
        for name in dict.fromkeys(hand.grasp_map.values())
        if hand.preshape(name).design_object is None
    ]
    for trial in hold_trials(hand, backend):
        if not trial.held:
            problems.append(
                f"preshape {trial.preshape!r} ({trial.grasp.value}): the hand alone does not "
                f"hold its design object: {trial.outcome.failure_reason}"
            )
    return problems
