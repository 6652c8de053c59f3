"""Preshapes synthesised from the human reference grasps: no joint angle typed by hand.

For each human grasp, on experiment A's object with the palm where the human reference
puts it (strategy/reference_poses.py), the synthesis searches a small space of
preshapes built from the joint roles of the hand's URDF (specs/draft.py):

- which real fingers close (all of them, or the thumb with one or two neighbours, the
  others curled out of the way), how far the curling joints start closed (the open
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
fingers, compared with the human reference's (metrics/virtual_fingers.py). The
objective is the virtual-finger position error [mm] plus the orientation error [deg],
plus 30 per virtual finger more or fewer than the human's, plus 60 per whole closing
between the first finger's touch and the last's (a finger that arrives first pushes
the object away: the fingers should meet it together), plus 150 times the contacts'
unbalanced push (unit forces along the normals, the table taking the downward part:
fingers that all push one way roll the object off), plus 1 per mm the hand must be
raised off the table (as the planner raises it, which moves the object in the hand);
a candidate whose open hand
lies in the object, or that touches with fewer than two real fingers, is refused. A
coordinate search (each parameter in turn, twice) finds the best; the best 16 are
ranked again by their worst objective with the object 1 cm off its place along each
horizontal axis (a finger nudges it as the hand closes: a grasp that works only where
the object stands exactly is fragile); then the best candidates, in that order, go
through the held test with physics (the hand alone, as
check-hand's experiment A trial): the first that holds is kept (another assignment of
fingers, roll or aperture when the best does not hold). None holding, the best is kept
and the table says so.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from itertools import combinations

import numpy as np
from numpy.typing import NDArray

from graspframe.common.contacts import OBJECT, Contact
from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import HUMAN_HAND, PALM, HumanGrasp
from graspframe.common.transforms import inv_T, make_T
from graspframe.hal.descriptions import DesignObject, HandDescription, HandPreshape
from graspframe.hal.drivers import Backend
from graspframe.hal.objects import ObjectDescription
from graspframe.metrics.virtual_fingers import compare, virtual_fingers_from_contacts
from graspframe.specs.draft import HandDraft, draft_hand, posture_table
from graspframe.strategy.held_check import HeldTest
from graspframe.strategy.planner import PlannerParams, PlanningError, object_in_palm

ROLLS_DEG = (0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)
OPEN_FRACTIONS = (0.0, 0.15, 0.3, 0.45)
RAISES = 2  # times a candidate is raised off the table before it is refused
CLOSE_FRACTIONS = (1.0, 0.75, 0.5)  # of the way from rest to the closing limit
SPREADS = (0.0, 1.0 / 3.0)  # of the way from rest to a spread joint's far limit
SHIFTS_X = (-0.045, -0.03, -0.015, 0.0, 0.015, 0.03, 0.045)  # [m] grasp centre along palm x
SHIFTS_Y = (-0.04, -0.02, 0.0, 0.02, 0.04)  # [m] along palm y
STANDOFFS = (0.0, 0.015, 0.03)  # [m] non-volar: beyond the planner's palm clearance
VF_COUNT_COST = 30.0  # objective per virtual finger more or fewer than the human's
# Penalties of a refused candidate (the search walks through them to feasible ones).
INSIDE_COST = 200.0  # per link of the open hand in the object
TABLE_COST, TABLE_COST_PER_MM = 100.0, 10.0
FEW_FINGERS_COST = 300.0
STAGGER_COST = 60.0  # per whole closing between the first finger's touch and the last's
RAISE_COST_PER_MM = 1.0  # a raise off the table moves the object in the hand
IMBALANCE_COST = 150.0  # times the contacts' unbalanced push (0..1, see _imbalance)
PASSES = 2  # of the coordinate search
ROBUST_SHIFT = 0.01  # [m]
ROBUST_CANDIDATES = 16  # re-ranked by their worst objective with the object shifted
HELD_TRIALS = 6  # candidates tried with physics, best first
SURFACE_SAMPLES = 20000  # points of the object's surface touches are projected on
VOLAR_GAP = 0.003  # [m] a volar candidate is closed with the object this far off the palm


@dataclass(frozen=True)
class Choice:
    """One candidate preshape's parameters (see the module docstring)."""

    fingers: tuple[str, ...]
    roll_deg: float = 0.0
    thumb: tuple[tuple[str, float], ...] = ()
    spread: float = 0.0
    open_fraction: float = 0.15
    close_fraction: float = 1.0
    shift_x: float = 0.0
    shift_y: float = 0.0
    standoff: float = 0.0


@dataclass(frozen=True)
class Evaluated:
    """A candidate closed kinematically: its preshape, the objective (inf: refused, with
    `refused` saying why), the errors and the real fingers that touched."""

    choice: Choice
    preshape: HandPreshape
    cost: float
    position_err_mm: float = math.nan
    orientation_err_deg: float = math.nan
    touched: tuple[str, ...] = ()
    refused: str | None = None


@dataclass
class GraspSynthesis:
    """What the synthesis found for one human grasp: the kept candidate, its held
    verdict (None: not tested), the errors measured in the held trial's contacts, and
    every physics trial (candidate, held, why not)."""

    grasp: HumanGrasp
    obj: ObjectDescription
    chosen: Evaluated
    held: bool | None
    failure: str | None = None
    measured_position_err_mm: float | None = None
    measured_orientation_err_deg: float | None = None
    trials: list[tuple[Evaluated, bool, str | None]] = field(default_factory=list)
    evaluated: int = 0
    seconds: float = 0.0


@dataclass
class Synthesis:
    """Every grasp's synthesis, the preshape each maps to (merged when two are equal)."""

    grasps: list[GraspSynthesis]
    grasp_map: dict[str, str]
    preshapes: dict[str, HandPreshape]
    seconds: float = 0.0


def roles_of(hand: HandDescription) -> tuple[HandDraft, dict[str, str]]:
    """The URDF's drafted roles for `hand` and the draft finger of each of the hand's
    real fingers (matched by their links)."""
    draft = draft_hand(hand.model_path)
    names = {}
    for finger, links in hand.real_fingers.items():
        if finger == PALM:
            continue
        best = max(draft.fingers.values(), key=lambda f: len(set(f.links) & set(links)))
        if not set(best.links) & set(links):
            raise GraspframeError(
                f"hand {hand.name!r}: real finger {finger!r} holds none of the URDF's finger "
                "links; the synthesis needs its fingers to be the URDF's chains"
            )
        names[finger] = best.name
    return draft, names


class _Space:
    """Builds and evaluates candidate preshapes of one hand for one grasp."""

    def __init__(
        self,
        hand: HandDescription,
        draft: HandDraft,
        names: Mapping[str, str],
        grasp: HumanGrasp,
        obj: ObjectDescription,
        T_object_human_palm: NDArray[np.float64],
        human_contacts: Sequence[Contact],
        human_fingers: Sequence[str],
    ):
        from scipy.spatial import cKDTree

        from graspframe.robot_models.shapes import object_mesh

        self.hand, self.draft, self.grasp, self.obj = hand, draft, grasp, obj
        self.finger_of_draft = {d: f for f, d in names.items()}
        self.draft_of = dict(names)
        self.T_object_human_palm = T_object_human_palm
        self.human = virtual_fingers_from_contacts(list(human_contacts))
        self.human_fingers = list(human_fingers)
        # The object's surface, densely sampled with its normals: touches are projected
        # on the nearest sample.
        mesh = object_mesh(obj)
        samples, faces = mesh.sample(SURFACE_SAMPLES, return_index=True, seed=0)
        self.surface = np.vstack([np.asarray(mesh.vertices), samples])
        vertex_normals = np.asarray(mesh.vertex_normals)
        self.normals = np.vstack([vertex_normals, np.asarray(mesh.face_normals)[faces]])
        self.tree = cKDTree(self.surface)
        self.thumb = next((f for f, d in names.items() if d == draft.thumb), None)
        self.cache: dict[Choice, Evaluated] = {}

    # -- candidates ---------------------------------------------------------------------

    def finger_sets(self) -> list[tuple[str, ...]]:
        fingers = [f for f in self.hand.real_fingers if f != PALM]
        sets = [tuple(fingers)]
        others = [f for f in fingers if f != self.thumb]
        if self.thumb is not None and len(others) >= 2:
            for k in (1, 2):
                if k < len(others):
                    sets += [(self.thumb, *c) for c in combinations(others, k)]
        return sets

    def thumb_values(self) -> list[tuple[tuple[str, float], ...]]:
        from graspframe.specs.draft import placing_grid

        if self.thumb is None:
            return [()]
        finger = self.draft.fingers[self.draft_of[self.thumb]]
        return [tuple(sorted(v.items())) for v in placing_grid(finger, self.draft.joints)]

    def initial(self) -> Choice:
        thumbs = self.thumb_values()
        return Choice(fingers=self.finger_sets()[0], thumb=thumbs[len(thumbs) // 2])

    def axes(self, choice: Choice) -> list[list[Choice]]:
        """Per parameter, the candidates that change it alone."""
        volar = self.grasp.volar_for_robot
        return [
            [replace(choice, fingers=s) for s in self.finger_sets()],
            [replace(choice, roll_deg=r) for r in ROLLS_DEG],
            [replace(choice, thumb=t) for t in self.thumb_values()],
            [replace(choice, spread=s) for s in SPREADS],
            [replace(choice, shift_x=x) for x in SHIFTS_X],
            [replace(choice, shift_y=y) for y in SHIFTS_Y],
            [replace(choice, open_fraction=o) for o in OPEN_FRACTIONS],
            [replace(choice, close_fraction=c) for c in CLOSE_FRACTIONS],
            [] if volar else [replace(choice, standoff=s) for s in STANDOFFS],
        ]

    # -- building ------------------------------------------------------------------------

    def preshape(self, choice: Choice, name: str) -> HandPreshape:
        draft, joints = self.draft, self.draft.joints
        rest = draft.rest_q()
        open_q, closed_q = dict(rest), dict(rest)
        for finger, draft_name in self.draft_of.items():
            f = draft.fingers[draft_name]
            closing = finger in choice.fingers
            for j in f.flexion:
                if j not in rest:
                    continue  # a <mimic> follower
                limit = joints[j].upper if f.closing_sign[j] > 0 else joints[j].lower
                if closing:
                    open_q[j] = rest[j] + choice.open_fraction * (limit - rest[j])
                    closed_q[j] = rest[j] + choice.close_fraction * (limit - rest[j])
                else:  # curled out of the way
                    open_q[j] = closed_q[j] = limit
            for j in f.placing:
                if j not in rest or j in draft.held_at_rest:
                    continue
                if finger == self.thumb:
                    value = dict(choice.thumb).get(j, rest[j])
                else:
                    far = (
                        joints[j].upper
                        if abs(joints[j].upper) >= abs(joints[j].lower)
                        else joints[j].lower
                    )
                    value = rest[j] + choice.spread * (far - rest[j])
                open_q[j] = closed_q[j] = value
        R_object_palm = self._R_object_palm(choice)
        design = self._design(R_object_palm)
        extent = self.obj.extent_along(-R_object_palm[:, 2])
        volar = self.grasp.volar_for_robot
        height = extent if volar else extent + PlannerParams().palm_clearance + choice.standoff
        centre = (choice.shift_x, choice.shift_y, height)
        design = replace(design, centre=centre)
        return HandPreshape(
            name=name,
            open_q=open_q,
            closed_q=closed_q,
            delta=math.nan,
            grasp_center=centre,
            design_object=design,
            roll=math.radians(choice.roll_deg),
        )

    def _R_object_palm(self, choice: Choice) -> NDArray[np.float64]:
        return self.T_object_human_palm[:3, :3] @ _Rz(math.radians(choice.roll_deg))

    def _design(self, R_object_palm: NDArray[np.float64]) -> DesignObject:
        """The object as a design object in the palm frame (a box as its enclosing
        cylinder about its upright axis)."""
        half = self.obj.half_extents
        R_palm_object = R_object_palm.T
        if self.obj.shape == "sphere":
            return DesignObject("sphere", (0.0, 0.0, 0.0), float(half[0]))
        axis = tuple(float(v) for v in R_palm_object[:, 2])
        radius = float(math.hypot(half[0], half[1])) if self.obj.shape == "box" else float(half[0])
        return DesignObject("cylinder", (0.0, 0.0, 0.0), radius, axis, float(2 * half[2]))

    # -- evaluating ----------------------------------------------------------------------

    def evaluate(self, choice: Choice) -> Evaluated:
        if choice in self.cache:
            return self.cache[choice]
        result = self.score(self.preshape(choice, self.grasp.value), choice)
        self.cache[choice] = result
        return result

    def score(
        self, preshape: HandPreshape, choice: Choice, shift: tuple[float, float] = (0.0, 0.0)
    ) -> Evaluated:
        """The preshape closed kinematically on the object, scored (the roll is the
        preshape's own); shift: [m] the object moved along its (horizontal) x and y."""
        from graspframe.strategy.hand_geometry import closing_sweep

        hand = self.with_preshape(preshape)
        R_object_palm = self.T_object_human_palm[:3, :3] @ _Rz(preshape.roll)
        volar = self.grasp.volar_for_robot
        centre = np.array(object_in_palm(preshape, self.obj, R_object_palm, volar))
        if volar:  # the palm stops on touching: closed just before it, the palm clear
            centre[2] += VOLAR_GAP
        T_palm_object = make_T(R_object_palm.T, centre) @ make_T(np.eye(3), (*shift, 0.0))
        sweep = closing_sweep(hand, hand.preshape(preshape.name), self.obj, T_palm_object)
        low, depth = self._below_table(hand, sweep.configurations, T_palm_object)
        raised = 0.0
        for _ in range(RAISES):  # as the planner does: the hand raised off the table
            if not low:
                break
            raised += depth + 0.001
            T_palm_object = T_palm_object.copy()
            T_palm_object[:3, 3] -= T_palm_object[:3, :3] @ np.array([0.0, 0.0, depth + 0.001])
            sweep = closing_sweep(hand, hand.preshape(preshape.name), self.obj, T_palm_object)
            low, depth = self._below_table(hand, sweep.configurations, T_palm_object)
        result = Evaluated(choice, hand.preshape(preshape.name), math.inf, touched=sweep.touched)
        palm_links = set(self.hand.real_fingers[PALM])
        inside = [link for link in sweep.open_inside if link not in palm_links]
        refused, penalty = [], RAISE_COST_PER_MM * 1000 * raised
        if inside:
            refused.append(f"open, {', '.join(inside)} lie in the object")
            penalty += INSIDE_COST * len(inside)
        if low:
            refused.append(f"{low} reaches {1000 * depth:.0f} mm into the table's clearance")
            penalty += TABLE_COST + TABLE_COST_PER_MM * 1000 * depth
        if len(set(sweep.touched)) < 2:
            refused.append("fewer than two real fingers touch the object")
            penalty += FEW_FINGERS_COST
        errors = (math.nan, math.nan, 0.0)
        if sweep.touched:
            contacts = self._contacts(
                sweep.p_object_touch, sweep.finger_touch, T_palm_object, volar
            )
            robot = virtual_fingers_from_contacts(contacts)
            comparison = compare(
                robot,
                self.human,
                robot_real_fingers=list(self.hand.finger_names),
                human_real_fingers=self.human_fingers,
            )
            count = abs(len(robot.virtual_fingers) - len(self.human.virtual_fingers))
            # fingers that reach the object one after the other push it off first
            stagger = max(sweep.s_touch) - min(sweep.s_touch)
            imbalance = _imbalance(contacts)
            errors = (
                comparison.position_err_mm,
                comparison.orientation_err_deg,
                comparison.position_err_mm
                + comparison.orientation_err_deg
                + VF_COUNT_COST * count
                + STAGGER_COST * stagger
                + IMBALANCE_COST * imbalance,
            )
        else:
            penalty += FEW_FINGERS_COST
        result = replace(
            result,
            cost=errors[2] + penalty,
            position_err_mm=errors[0],
            orientation_err_deg=errors[1],
            refused="; ".join(refused) or None,
        )
        return result

    def _below_table(self, hand, configurations, T_palm_object) -> tuple[str | None, float]:
        """(the link that comes deepest within the planner's table clearance of the table
        while the hand closes, how deep [m]): the planner would raise the hand off the
        object. (None, 0) when none does."""
        from graspframe.hal.objects import TABLE_HEIGHT
        from graspframe.strategy.hand_geometry import lowest_points

        T_world_palm = self.obj.T_world_standing() @ inv_T(T_palm_object)
        lowest = lowest_points(hand, configurations, T_world_palm[:3, :3])
        limit = TABLE_HEIGHT + PlannerParams().table_clearance - T_world_palm[2, 3]
        below = [link for link, z in lowest.items() if z < limit]
        if not below:
            return None, 0.0
        link = min(below, key=lambda name: lowest[name])
        return link, float(limit - lowest[link])

    def with_preshape(self, preshape: HandPreshape) -> HandDescription:
        from graspframe.specs.hands import fingertip_height

        hand = replace(
            self.hand, preshapes={preshape.name: preshape}, grasp_map={self.grasp: preshape.name}
        )
        delta = fingertip_height(hand, hand.fingertip_frames)(preshape.open_q)
        return replace(hand, preshapes={preshape.name: replace(preshape, delta=max(delta, 0.0))})

    def _contacts(self, points, fingers, T_palm_object, volar) -> list[Contact]:
        """The sweep's touches projected on the object's surface (object frame), each with
        the surface normal there, a unit force into the object; the palm's, for a volar
        grasp, where the object's surface is nearest the palm origin."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        finger_list = list(fingers)
        if volar:
            palm_in_object = inv_T(T_palm_object)[:3, 3]
            points = np.vstack([points, palm_in_object])
            finger_list.append(PALM)
        _distance, nearest = self.tree.query(points)
        surface, normals = self.surface[nearest], self.normals[nearest]
        return [
            Contact(finger, finger, np.asarray(p), np.asarray(n), -np.asarray(n), frame=OBJECT)
            for finger, p, n in zip(finger_list, surface, normals, strict=True)
        ]

    def robust_cost(self, evaluated: Evaluated) -> float:
        """The worst objective with the object ROBUST_SHIFT off its place along each
        horizontal axis (an object a finger nudges while the hand closes): a grasp that
        only works where the object stands exactly is fragile."""
        costs = [evaluated.cost]
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            shifted = self.score(
                evaluated.preshape, evaluated.choice, (ROBUST_SHIFT * dx, ROBUST_SHIFT * dy)
            )
            costs.append(shifted.cost)
        return max(costs)

    def search(self) -> list[Evaluated]:
        """The coordinate search; every candidate evaluated, best first."""
        choice = self.initial()
        best = self.evaluate(choice)
        for _ in range(PASSES):
            for axis in self.axes(best.choice):
                for candidate in axis:
                    evaluated = self.evaluate(replace(candidate))
                    if evaluated.cost < best.cost:
                        best = evaluated
                # the next axis varies the best so far
            if not math.isfinite(best.cost):
                break
        return sorted(self.cache.values(), key=lambda e: e.cost)


def _imbalance(contacts: Sequence[Contact]) -> float:
    """How much the contacts, each pushing with a unit force along its normal into the
    object, push it one way: |sum of the forces| / their count (0: they balance, 1: all
    push the same way), the table taking what pushes the object down (object frame z is
    the world's up for an object standing on it)."""
    forces = np.array([c.f for c in contacts], dtype=float).reshape(-1, 3)
    forces /= np.maximum(np.linalg.norm(forces, axis=1, keepdims=True), 1e-12)
    net = forces.sum(axis=0)
    net[2] = max(net[2], 0.0)
    return float(np.linalg.norm(net) / max(len(forces), 1))


def _Rz(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _held_trial(
    hand: HandDescription, grasp: HumanGrasp, obj: ObjectDescription, backend: Backend,
    T_object_human_palm: NDArray[np.float64], held: HeldTest,
):  # fmt: skip
    """(held, failure, contacts in the object frame) of the hand alone grasping `obj`."""
    from graspframe.checks.grasps import _hand_alone

    try:
        outcome, _moments, _checked = _hand_alone(
            hand, grasp, backend, obj, T_object_palm=T_object_human_palm, held=held
        )
    except PlanningError as exc:
        return False, f"no plan: {exc}", []
    contacts = [c.in_object_frame(outcome.T_world_object_at_hold) for c in outcome.contacts]
    return outcome.success, outcome.failure_reason, contacts


def synthesize(
    hand: HandDescription,
    registry,
    backend: Backend,
    grasps: Sequence[HumanGrasp] = tuple(HumanGrasp),
    progress: Callable[[str], None] = lambda _message: None,
    held: HeldTest | None = None,
    test_held: bool = True,
) -> Synthesis:
    """Preshapes of `hand` for `grasps`, synthesised from the human reference grasps on
    experiment A's objects (module docstring); `registry` gives the objects and the
    human hand, `backend` simulates the human reference and the held trials."""
    from graspframe.strategy.human_reference import human_reference
    from graspframe.strategy.reference_poses import reference_placement

    started = time.perf_counter()
    held = held or HeldTest()
    draft, names = roles_of(hand)
    human = registry.get_hand(HUMAN_HAND)
    results = []
    for grasp in grasps:
        t0 = time.perf_counter()
        obj = registry.default_object_for(grasp)
        progress(f"{grasp.value}: the human reference on {obj.name}")
        reference = human_reference(grasp, obj, human, backend, held)
        T_object_human_palm = reference_placement(obj, human.preshape_for(grasp)).T_object_palm
        space = _Space(
            hand, draft, names, grasp, obj, T_object_human_palm, reference.contacts,
            human.finger_names,
        )  # fmt: skip
        if not reference.contacts:
            raise GraspframeError(f"the human reference of {grasp.value} has no contacts")
        progress(f"{grasp.value}: searching the preshapes (kinematic closing on {obj.name})")
        ranked = [e for e in space.search() if e.refused is None]
        # the best ROBUST_CANDIDATES, in the order of their worst objective nearby
        robust = sorted(ranked[:ROBUST_CANDIDATES], key=space.robust_cost)
        ranked = robust + ranked[ROBUST_CANDIDATES:]
        if not ranked:
            nearest = sorted(space.cache.values(), key=lambda e: e.cost)[:3]
            reasons = list(dict.fromkeys(e.refused or "" for e in nearest))
            raise GraspframeError(
                f"{hand.name} cannot make a {grasp.value} on {obj.name}: every candidate was "
                f"refused; the nearest: {' | '.join(reasons)}"
            )
        outcome = GraspSynthesis(grasp, obj, ranked[0], None, evaluated=len(space.cache))
        if test_held:
            for k, candidate in enumerate(_distinct(ranked)[:HELD_TRIALS], start=1):
                progress(f"{grasp.value}: held test {k} (physics, the hand alone on {obj.name})")
                trial_hand = space.with_preshape(candidate.preshape)
                ok, failure, contacts = _held_trial(
                    trial_hand, grasp, obj, backend, T_object_human_palm, held
                )
                outcome.trials.append((candidate, ok, failure))
                if ok or k == 1:
                    outcome.chosen, outcome.held, outcome.failure = candidate, ok, failure
                    outcome.measured_position_err_mm, outcome.measured_orientation_err_deg = (
                        _measured(contacts, space, hand)
                    )
                if ok:
                    break
        outcome.seconds = time.perf_counter() - t0
        results.append(outcome)
    preshapes, grasp_map = _merged(results)
    return Synthesis(results, grasp_map, preshapes, time.perf_counter() - started)


def _distinct(ranked: Sequence[Evaluated]) -> list[Evaluated]:
    """The candidates, best first, one per distinct (fingers, aperture, close, spread,
    standoff, thumb placing): what fails in physics is mostly one of these (fingers
    spread round a small object tip it over whatever the roll), so a failed held test
    asks for another of them."""
    seen, kept = set(), []
    for e in ranked:
        c = e.choice
        key = (
            c.fingers,
            c.roll_deg,
            c.open_fraction,
            c.close_fraction,
            c.spread,
            c.standoff,
            c.thumb,
        )
        if key not in seen:
            seen.add(key)
            kept.append(e)
    return kept


def _measured(contacts, space: _Space, hand: HandDescription) -> tuple[float | None, float | None]:
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


# -- the spec's preshape table --------------------------------------------------------------


def preshape_tables(synthesis: Synthesis, draft: HandDraft) -> str:
    """The [preshapes.*] tables, each with a comment: the grasp(s) it serves, its
    object, the virtual-finger errors (predicted by the kinematic closing, and measured
    in the held trial) and the held verdict."""
    lines = [
        "# Preshapes synthesised by graspframe from the human reference grasps (see",
        "# docs/synthesis.md): edit any value; `graspframe check-hand SPEC --synthesize`",
        "# rewrites them.",
    ]
    by_preshape: dict[str, list[GraspSynthesis]] = {}
    for result in synthesis.grasps:
        by_preshape.setdefault(synthesis.grasp_map[result.grasp.value], []).append(result)
    for name, preshape in synthesis.preshapes.items():
        served = by_preshape[name]
        result = served[0]
        chosen = result.chosen
        lines.append("")
        also = [r.grasp.value for r in served[1:]]
        lines.append(
            f"# {result.grasp.value} on {result.obj.name}"
            + (f" (also serves {', '.join(also)}: the same preshape)" if also else "")
            + f": fingers {', '.join(chosen.choice.fingers)}, roll {chosen.choice.roll_deg:g} deg, "
            f"open {100 * chosen.choice.open_fraction:.0f} % closed."
        )
        lines.append(
            f"# Virtual-finger error: predicted {chosen.position_err_mm:.1f} mm, "
            f"{chosen.orientation_err_deg:.1f} deg"
            + (
                f"; measured {result.measured_position_err_mm:.1f} mm, "
                f"{result.measured_orientation_err_deg:.1f} deg"
                if result.measured_position_err_mm is not None
                and result.measured_orientation_err_deg is not None
                else ""
            )
            + "."
        )
        if result.held is None:
            lines.append("# Held: not tested.")
        elif result.held:
            lines.append(f"# Held: yes (held trial {len(result.trials)} of {len(result.trials)}).")
        else:
            lines.append(f"# Held: NO after {len(result.trials)} candidates: {result.failure}")
        lines.append(f"[preshapes.{name}]")
        centre = ", ".join(f"{round(v, 4):g}" for v in preshape.grasp_center_palm)
        lines.append(f"grasp_center = [{centre}]")
        lines.append(f"roll_deg = {chosen.choice.roll_deg:g}")
        design = preshape.design_object
        assert design is not None
        vector = lambda v: "[" + ", ".join(f"{round(float(x), 4):g}" for x in v) + "]"  # noqa: E731
        if design.shape == "sphere":
            lines.append(
                f'design_object = {{ shape = "sphere", centre = {vector(design.centre)}, '
                f"radius = {round(design.radius, 4):g} }}"
            )
        else:
            assert design.axis is not None and design.length is not None
            lines.append(
                f'design_object = {{ shape = "cylinder", centre = {vector(design.centre)}, '
                f"radius = {round(design.radius, 4):g}, axis = {vector(design.axis)}, "
                f"length = {round(design.length, 4):g} }}"
            )
        lines += posture_table(name, "open", preshape.open_q, draft.joints)
        lines += posture_table(name, "closed", preshape.closed_q, draft.joints)
    return "\n".join(lines)
