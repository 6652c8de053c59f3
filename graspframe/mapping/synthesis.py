"""Preshapes synthesised from the human reference grasps: no joint angle typed by hand.

For each human grasp, on experiment A's object with the palm where the human reference
puts it (strategy/reference_poses.py), the synthesis searches a small space of
preshapes built from the joint roles of the hand's URDF (specs/draft.py):

- which real fingers close (all of them, or the thumb with one or two neighbours, the
  others stowed out of the way), how far the curling joints start closed (the open
  aperture), the thumb's placing joints (rotation, abduction) and the other fingers'
  spread, the palm's roll about its normal (in 45 deg steps), where the object
  sits in the palm (the grasp centre along the palm's x and y) and, for a grasp the
  robot makes without the palm, the standoff;
- closed: every closing finger's curling joints at, or 75 % or 50 % of the way to,
  the limit that closes them (the fingers stop on the object before it; a partial
  close keeps a curling finger off the table).

Each candidate is closed kinematically on the object (strategy/hand_geometry.py's
closing sweep: each finger stops where one of its links first touches it, Pinocchio
and coal); its contacts, projected on the object's surface, give the robot's virtual
fingers, compared with the human reference's (metrics/virtual_fingers.py); a finger's
touch on a face that looks up grips nothing and is left out (mapping/grip.py). The
objective is the virtual-finger position error [mm] plus the orientation error [deg],
plus 30 per virtual finger more or fewer than the human's, plus 60 per whole closing
between the first finger's touch and the last's (a finger that arrives first pushes
the object away: the fingers should meet it together), plus 150 times the contacts'
unbalanced push (unit forces along the normals, the table taking the downward part:
fingers that all push one way roll the object off), plus 1 per mm the hand must be
raised off the table (as the planner raises it, which moves the object in the hand);
a candidate is refused (mapping/refusals.py) when its open hand lies in the object, when
a finger reaches the object before the palm reaches its goal on the planner's approach
(the volar strategy would back off, a closing from the standoff would start off the
object), when links of its open hand overlap each other (check-hand fails such a
posture), when closed in free space no two fingers meet (check-hand's closing check),
or when fewer than two real fingers touch or grip; links that overlap only
where the fingers stop cost 20 each (a real finger closing onto the palm stops there;
the simulator lets it through). Fingers that do not close are stowed curled, or 60 %,
30 % or 0 % of the way. A
coordinate search (each parameter in turn, twice, from three thumb placings, each with
the object where it sits best in the palm for it) finds the best; the best 16 are
ranked again by their worst objective with the object 1 cm off its place along each
horizontal axis (a finger nudges it as the hand closes: a grasp that works only where
the object stands exactly is fragile); then the best candidates, in that order, go
through the held test with physics (the hand alone, as
check-hand's experiment A trial, then on its design object as check-hand's design
trial): the first that holds both is kept (another assignment of
fingers, roll or aperture when the best does not hold), else the first that held
experiment A's object (the table says its design object was not held). None holding,
the best is kept and the table says so.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from itertools import zip_longest

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import Contact
from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import HUMAN_HAND, HumanGrasp
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.drivers import Backend
from graspframe.hal.objects import ObjectDescription
from graspframe.mapping.candidates import CandidateSpace
from graspframe.mapping.choices import Evaluated
from graspframe.mapping.roles import roles_of
from graspframe.metrics.virtual_fingers import compare, virtual_fingers_from_contacts
from graspframe.specs.draft import HandDraft
from graspframe.specs.draft_text import written_posture
from graspframe.strategy.held_check import HeldTest
from graspframe.strategy.planner import PlanningError

ROBUST_CANDIDATES = 16  # re-ranked by their worst objective with the object shifted
HELD_TRIALS = 16  # candidates tried with physics (1 to 2 s each when not held)


@dataclass
class GraspSynthesis:
    """What the synthesis found for one human grasp: the kept candidate, its held
    verdict on experiment A's object (None: not tested) and on its design object, the
    errors measured in the held trial's contacts, and every physics trial (candidate,
    held both, why not)."""

    grasp: HumanGrasp
    obj: ObjectDescription
    chosen: Evaluated
    held: bool | None
    failure: str | None = None
    measured_position_err_mm: float | None = None
    measured_orientation_err_deg: float | None = None
    trials: list[tuple[Evaluated, bool, str | None]] = field(default_factory=list)
    kept_trial: int = 0  # which of the trials was kept (1-based; 0: none ran)
    design_failure: str | None = None  # held, but not its design object: why
    evaluated: int = 0
    seconds: float = 0.0


@dataclass
class Synthesis:
    """Every grasp's synthesis, the preshape each maps to (merged when two are equal)."""

    grasps: list[GraspSynthesis]
    grasp_map: dict[str, str]
    preshapes: dict[str, HandPreshape]
    seconds: float = 0.0
    # grasp -> why the hand cannot make it (every candidate refused): no preshape
    impossible: dict[str, str] = field(default_factory=dict)


def _held_trial(
    hand: HandDescription, grasp: HumanGrasp, obj: ObjectDescription, backend: Backend,
    T_object_human_palm: NDArray[np.float64], held: HeldTest,
):  # fmt: skip
    """(held, failure, contacts in the object frame, design failure) of the hand alone
    grasping `obj` where the human reference puts the palm; held, its design object (the
    preshape's own object in its palm, as check-hand grasps it) is grasped too, and the
    design failure says why it was not held (None: held, or not tried)."""
    from graspframe.checks.grasps import hand_alone_grasp

    try:
        outcome = hand_alone_grasp(
            hand, grasp, backend, obj, T_object_palm=T_object_human_palm, held=held
        )
        design = hand_alone_grasp(hand, grasp, backend, held=held) if outcome.success else None
    except PlanningError as exc:
        return False, f"no plan: {exc}", [], None
    except (GraspframeError, ValueError, FloatingPointError) as exc:
        # the physics of a bad candidate can blow up (poses not finite): not held
        return False, f"the simulation failed ({type(exc).__name__}: {exc})", [], None
    contacts = [c.in_object_frame(outcome.T_world_object_at_hold) for c in outcome.contacts]
    design_failure = None
    if design is not None and not design.success:
        design_failure = f"its design object: {design.failure_reason}"
    return outcome.success, outcome.failure_reason, contacts, design_failure


def synthesize(
    hand: HandDescription,
    registry,
    backend: Backend,
    grasps: Sequence[HumanGrasp] = tuple(HumanGrasp),
    progress: Callable[[str], None] = lambda _message: None,
    held: HeldTest | None = None,
    test_held: bool = True,
    workers: int = 1,
) -> Synthesis:
    """Preshapes of `hand` for `grasps`, synthesised from the human reference grasps on
    experiment A's objects (module docstring); `registry` gives the objects and the
    human hand, `backend` simulates the human reference and the held trials. workers:
    grasps synthesised at once, each in a process of its own (mapping/parallel.py; its
    registry the default one) when more than 1."""
    started = time.perf_counter()
    held = held or HeldTest()
    roles = roles_of(hand)  # the URDF drafted again once, for every grasp
    if workers > 1 and len(grasps) > 1:
        from graspframe.mapping.parallel import synthesize_in_workers

        found = synthesize_in_workers(
            hand, roles, backend.name, grasps, held, test_held, workers, progress
        )
    else:
        found = [
            synthesize_grasp(hand, roles, registry, backend, grasp, held, test_held, progress)
            for grasp in grasps
        ]
    results = [r for r in found if isinstance(r, GraspSynthesis)]
    impossible = {g.value: r for g, r in zip(grasps, found, strict=True) if isinstance(r, str)}
    if not results:  # a spec needs one preshape at least
        raise GraspframeError("; ".join(impossible.values()))
    preshapes, grasp_map = _merged(results)
    return Synthesis(results, grasp_map, preshapes, time.perf_counter() - started, impossible)


def synthesize_grasp(
    hand: HandDescription,
    roles: tuple[HandDraft, dict[str, str]],
    registry,
    backend: Backend,
    grasp: HumanGrasp,
    held: HeldTest,
    test_held: bool = True,
    progress: Callable[[str], None] = lambda _message: None,
) -> GraspSynthesis | str:
    """One grasp's synthesis (module docstring), or why the hand cannot make it (every
    candidate refused); roles: the hand's `roles_of`."""
    from graspframe.strategy.human_reference import human_reference
    from graspframe.strategy.reference_poses import reference_placement

    draft, names = roles
    human = registry.get_hand(HUMAN_HAND)
    t0 = time.perf_counter()
    obj = registry.default_object_for(grasp)
    progress(f"{grasp.value}: the human reference on {obj.name}")
    reference = human_reference(grasp, obj, human, backend, held)
    T_object_human_palm = reference_placement(obj, human.preshape_for(grasp)).T_object_palm
    space = CandidateSpace(
        hand, draft, names, grasp, obj, T_object_human_palm, reference.contacts,
        human.finger_names,
    )  # fmt: skip
    if not reference.contacts:
        raise GraspframeError(f"the human reference of {grasp.value} has no contacts")
    progress(f"{grasp.value}: searching the preshapes (kinematic closing on {obj.name})")
    found = space.search()  # best first
    ranked = [e for e in found if e.refused is None]
    # the best ROBUST_CANDIDATES, in the order of their worst objective nearby
    robust = sorted(ranked[:ROBUST_CANDIDATES], key=space.robust_cost)
    ranked = robust + ranked[ROBUST_CANDIDATES:]
    if not ranked:
        reasons = list(dict.fromkeys(e.refused or "" for e in found[:3]))
        impossible = (
            f"{hand.name} cannot make a {grasp.value} on {obj.name}: every candidate was "
            f"refused; the nearest: {' | '.join(reasons)}"
        )
        progress(f"{grasp.value}: no preshape ({impossible})")
        return impossible
    outcome = GraspSynthesis(grasp, obj, ranked[0], None, evaluated=len(space.cache))
    if test_held:
        _held_trials(outcome, _distinct(ranked)[:HELD_TRIALS], space, draft, backend, held,
                     T_object_human_palm, progress)  # fmt: skip
    outcome.seconds = time.perf_counter() - t0
    return outcome


def _held_trials(
    outcome: GraspSynthesis,
    candidates: Sequence[Evaluated],
    space: CandidateSpace,
    draft,
    backend: Backend,
    held: HeldTest,
    T_object_human_palm: NDArray[np.float64],
    progress: Callable[[str], None],
) -> None:
    """The candidates grasped in turn (`_held_trial`) until one holds experiment A's
    object and its design object; `outcome` keeps it, else the first that held
    experiment A's object (its design failure said), else the first candidate."""
    grasp, obj = outcome.grasp, outcome.obj
    kept: tuple | None = None  # (k, candidate, ok, failure, contacts, design_failure)
    for k, candidate in enumerate(candidates, start=1):
        progress(f"{grasp.value}: held test {k} (physics, the hand alone on {obj.name})")
        # what the table writes is what is tested: a marginal grasp can flip on a
        # 0.01 deg rounding
        trial_hand = space.with_preshape(candidate.preshape)
        written = _as_written(trial_hand.preshapes[grasp.value], draft.joints)
        trial_hand = replace(trial_hand, preshapes={grasp.value: written})
        candidate = replace(candidate, preshape=written)
        ok, failure, contacts, design_failure = _held_trial(
            trial_hand, grasp, obj, backend, T_object_human_palm, held
        )
        outcome.trials.append((candidate, ok and design_failure is None, failure or design_failure))
        trial = (k, candidate, ok, failure, contacts, design_failure)
        if kept is None or (ok and not kept[2]):
            kept = trial
        if ok and design_failure is None:
            kept = trial
            break
    if kept is None:
        return
    k, candidate, ok, failure, contacts, design_failure = kept
    outcome.chosen, outcome.held, outcome.failure = candidate, ok, failure
    outcome.kept_trial, outcome.design_failure = k, design_failure
    outcome.measured_position_err_mm, outcome.measured_orientation_err_deg = _measured(
        contacts, space, space.hand
    )


def _distinct(ranked: Sequence[Evaluated]) -> list[Evaluated]:
    """The candidates for the held trials, best first, one per distinct (fingers, roll,
    aperture, close, spread, standoff, thumb placing), taken in turn from two queues:
    the next best of any arrangement, and the best of an arrangement (the closing
    fingers, the thumb placing and the standoff) not tried yet. What fails in physics is
    often the arrangement (a thumb hanging below the palm sweeps a light object over
    whatever the roll or the aperture), sometimes only the roll or the aperture."""
    seen: set = set()
    best, new_arrangement = [], []
    arrangements: set = set()
    for e in ranked:
        c = e.choice
        arrangement = (c.fingers, c.thumb, c.standoff)
        key = (*arrangement, c.roll_deg, c.open_fraction, c.close_fraction, c.spread)
        if key in seen:
            continue
        seen.add(key)
        best.append(e)
        if arrangement not in arrangements:
            arrangements.add(arrangement)
            new_arrangement.append(e)
    kept: list[Evaluated] = []
    taken: set[int] = set()  # by identity: comparing candidates field by field is slow
    for pair in zip_longest(best, new_arrangement[1:]):
        for e in pair:
            if e is not None and id(e) not in taken:
                taken.add(id(e))
                kept.append(e)
    return kept


def _as_written(preshape: HandPreshape, joints) -> HandPreshape:
    """The preshape as the spec's table (mapping/tables.py) writes it and it reads back:
    joint values to 0.01 deg (specs/draft_text.py's written_posture), lengths to 0.1 mm,
    the delta 0 at least."""

    def rounded(values) -> tuple[float, float, float]:
        x, y, z = (round(float(v), 4) for v in values)
        return x, y, z

    design = preshape.design_object
    if design is not None:
        design = replace(
            design,
            centre=rounded(design.centre),
            radius=round(design.radius, 4),
            axis=None if design.axis is None else rounded(design.axis),
            length=None if design.length is None else round(design.length, 4),
        )
    return replace(
        preshape,
        open_q=written_posture(preshape.open_q, joints),
        closed_q=written_posture(preshape.closed_q, joints),
        grasp_center=rounded(preshape.grasp_center_palm),
        delta=round(max(preshape.delta, 0.0), 4),
        design_object=design,
    )


def _measured(
    contacts: Sequence[Contact], space: CandidateSpace, hand: HandDescription
) -> tuple[float | None, float | None]:
    """The virtual-finger errors of a held trial's contacts (object frame)."""
    if not contacts:
        return None, None
    try:
        comparison = compare(
            virtual_fingers_from_contacts(contacts),
            space.human,
            robot_real_fingers=list(hand.finger_names),
            human_real_fingers=space.human_fingers,
        )
    except GraspframeError:
        return None, None
    return comparison.position_err_mm, comparison.orientation_err_deg


def _merged(results: Sequence[GraspSynthesis]) -> tuple[dict[str, HandPreshape], dict[str, str]]:
    """One preshape per grasp, named after it; two grasps whose preshapes are equal
    (postures within 0.1 deg, centre within 1 mm, the same roll and design) share one."""
    preshapes: dict[str, HandPreshape] = {}
    grasp_map: dict[str, str] = {}
    for result in results:
        preshape = replace(result.chosen.preshape, name=result.grasp.value)
        same = next((p for p in preshapes.values() if _equal(p, preshape)), None)
        if same is None:
            preshapes[preshape.name] = preshape
            grasp_map[result.grasp.value] = preshape.name
        else:
            grasp_map[result.grasp.value] = same.name
    return preshapes, grasp_map


def _equal(a: HandPreshape, b: HandPreshape) -> bool:
    def close(qa, qb):
        return qa.keys() == qb.keys() and all(abs(qa[k] - qb[k]) < math.radians(0.1) for k in qa)

    return (
        close(a.open_q, b.open_q)
        and close(a.closed_q, b.closed_q)
        and abs(a.roll - b.roll) < 1e-6
        and np.allclose(a.grasp_center_palm, b.grasp_center_palm, atol=0.001)
        and a.design_object == b.design_object
    )
