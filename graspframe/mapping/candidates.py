"""The candidate preshapes of the synthesis (graspframe/mapping/synthesis.py) for one
hand and one human grasp: built from the joint roles of the hand's URDF draft, closed
kinematically on experiment A's object where the human reference puts the palm, and
scored by the objective the synthesis's docstring gives."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from itertools import combinations

import numpy as np
from numpy.typing import NDArray

from graspframe.checks.grasps import closing_problems
from graspframe.common.contacts import OBJECT, Contact
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.common.transforms import inv_T, make_T
from graspframe.hal.descriptions import DesignObject, HandDescription, HandPreshape
from graspframe.hal.objects import ObjectDescription
from graspframe.mapping.choices import (
    CLOSE_FRACTIONS,
    OPEN_FRACTIONS,
    ROLLS_DEG,
    SHIFTS_X,
    SHIFTS_Y,
    SPREADS,
    STANDOFFS,
    STOW_FRACTIONS,
    Choice,
    Evaluated,
)
from graspframe.mapping.grip import epsilon_of, gripping, imbalance
from graspframe.mapping.refusals import approach_refusal, below_table, self_collisions
from graspframe.metrics.virtual_fingers import compare, virtual_fingers_from_contacts
from graspframe.robot_models.model import CollisionModel, model_of
from graspframe.specs.draft import HandDraft
from graspframe.strategy.planner import PlannerParams, object_in_palm

RAISES = 2  # times a candidate is raised off the table before it is refused
VF_COUNT_COST = 30.0  # objective per virtual finger more or fewer than the human's
# Penalties of a refused candidate (the search walks through them to feasible ones).
INSIDE_COST = 200.0  # per link of the open hand in the object
TABLE_COST, TABLE_COST_PER_MM = 100.0, 10.0
FEW_FINGERS_COST = 300.0
APPROACH_COST = 200.0  # a finger on the object before the palm reaches its goal
SELF_COLLISION_COST = 200.0  # per pair of links that overlap in the open posture
CLOSING_COST = 200.0  # closed in free space, no two fingers meet (check-hand fails it)
# Closed, a finger that closes onto the palm or another finger stops there on the real
# hand (the simulator lets it through): a penalty, not a refusal.
CLOSED_OVERLAP_COST = 20.0  # per pair
STAGGER_COST = 60.0  # per whole closing between the first finger's touch and the last's
RAISE_COST_PER_MM = 1.0  # a raise off the table moves the object in the hand
IMBALANCE_COST = 150.0  # times the contacts' unbalanced push (0..1, see _imbalance)
PASSES = 2  # of the coordinate search
STARTS = 3  # thumb placings the search starts from
ROBUST_SHIFT = 0.01  # [m]
SURFACE_SAMPLES = 20000  # points of the object's surface touches are projected on
VOLAR_GAP = 0.003  # [m] a volar candidate is closed with the object this far off the palm


class CandidateSpace:
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
        from graspframe.specs.hands import fingertip_height

        # one collision model for every candidate (the preshapes do not change the model)
        self.fingertip_height = fingertip_height(hand, hand.fingertip_frames)
        self.collision_model = CollisionModel(model_of(hand))
        self.spreads = any(
            j in draft.rest_q() and j not in draft.held_at_rest
            for finger, draft_name in self.draft_of.items()
            if finger != self.thumb
            for j in draft.fingers[draft_name].placing
        )

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
        from graspframe.specs.draft_kinematics import placing_grid

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
            [replace(choice, stow_fraction=f) for f in STOW_FRACTIONS],
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
                else:  # curled out of the way, as far as the palm lets it
                    stowed = rest[j] + choice.stow_fraction * (limit - rest[j])
                    open_q[j] = closed_q[j] = stowed
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
        return self.T_object_human_palm[:3, :3] @ Rz(math.radians(choice.roll_deg))

    def _design(self, R_object_palm: NDArray[np.float64]) -> DesignObject:
        """The object as a design object in the palm frame (a box as its enclosing
        cylinder about its upright axis)."""
        half = self.obj.half_extents
        R_palm_object = R_object_palm.T
        if self.obj.shape == "sphere":
            return DesignObject("sphere", (0.0, 0.0, 0.0), float(half[0]))
        x, y, z = (float(v) for v in R_palm_object[:, 2])
        axis = (x, y, z)
        radius = float(math.hypot(half[0], half[1])) if self.obj.shape == "box" else float(half[0])
        return DesignObject("cylinder", (0.0, 0.0, 0.0), radius, axis, float(2 * half[2]))

    # -- evaluating ----------------------------------------------------------------------

    def evaluate(self, choice: Choice) -> Evaluated:
        # parameters that change nothing on this hand take one value: one candidate
        if set(choice.fingers) == set(self.finger_sets()[0]):
            choice = replace(choice, stow_fraction=1.0)  # no finger stowed
        if not self.spreads:
            choice = replace(choice, spread=0.0)  # no finger but the thumb has placing joints
        if choice in self.cache:
            return self.cache[choice]
        result = self.score(self.preshape(choice, self.grasp.value), choice)
        self.cache[choice] = result
        return result

    def score(
        self,
        preshape: HandPreshape,
        choice: Choice,
        shift: tuple[float, float] = (0.0, 0.0),
        T_palm_goal: NDArray[np.float64] | None = None,
    ) -> Evaluated:
        """The preshape closed kinematically on the object, scored (the roll is the
        preshape's own); shift: [m] the object moved along its (horizontal) x and y;
        T_palm_goal: the object in the palm where the planner's goal puts it (default:
        where the preshape's grasp centre puts it, raised off the table here)."""
        from graspframe.strategy.hand_geometry import closing_sweep

        hand = self.with_preshape(preshape)
        R_object_palm = self.T_object_human_palm[:3, :3] @ Rz(preshape.roll)
        volar = self.grasp.volar_for_robot
        centre = np.array(object_in_palm(preshape, self.obj, R_object_palm, volar))
        if volar:  # the palm stops on touching: closed just before it, the palm clear
            centre[2] += VOLAR_GAP
        T_palm_object = make_T(R_object_palm.T, centre) @ make_T(np.eye(3), (*shift, 0.0))
        if T_palm_goal is not None:
            T_palm_object = T_palm_goal.copy()
            T_palm_object[2, 3] += VOLAR_GAP if volar else 0.0
        sweep = closing_sweep(hand, hand.preshape(preshape.name), self.obj, T_palm_object)
        low, depth = below_table(self.obj, hand, sweep.configurations, T_palm_object)
        raised = 0.0
        # as the planner does: the hand raised off the table (the planner's goal is raised)
        for _ in range(0 if T_palm_goal is not None else RAISES):
            if not low:
                break
            raised += depth + 0.001
            T_palm_object = T_palm_object.copy()
            T_palm_object[:3, 3] -= T_palm_object[:3, :3] @ np.array([0.0, 0.0, depth + 0.001])
            sweep = closing_sweep(hand, hand.preshape(preshape.name), self.obj, T_palm_object)
            low, depth = below_table(self.obj, hand, sweep.configurations, T_palm_object)
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
        first = approach_refusal(self.obj, hand, preshape, T_palm_object)
        if first is not None:
            refused.append(first)
            penalty += APPROACH_COST
        open_overlaps, closed_overlaps = self_collisions(self.collision_model, sweep.configurations)
        if open_overlaps:
            more = len(open_overlaps) - 1
            refused.append(
                f"open, links {' and '.join(open_overlaps[0])} overlap"
                + (f" (and {more} more pairs)" if more else "")
            )
            penalty += SELF_COLLISION_COST * len(open_overlaps)
        penalty += CLOSED_OVERLAP_COST * len(closed_overlaps)
        closing = closing_problems(hand)  # check-hand's: some fingers meet when closed
        if closing:
            refused.append(closing[0].split(": ", 1)[1])
            penalty += CLOSING_COST
        if len(set(sweep.touched)) < 2:
            refused.append("fewer than two real fingers touch the object")
            penalty += FEW_FINGERS_COST
        errors, unbalanced, epsilon = (math.nan, math.nan, 0.0), math.nan, math.nan
        contacts = []
        if sweep.touched:
            # a finger's touch on a face that looks up holds nothing (mapping/grip.py)
            contacts = gripping(
                self._contacts(sweep.p_object_touch, sweep.finger_touch, T_palm_object, volar)
            )
            gripped = {c.real_finger for c in contacts if c.real_finger != PALM}
            if len(set(sweep.touched)) >= 2 and len(gripped) < 2:
                refused.append(
                    f"{len(gripped)} real finger{'' if len(gripped) == 1 else 's'} grip the "
                    "object; the other touches press on a face that looks up"
                )
                penalty += FEW_FINGERS_COST
        if contacts:
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
            unbalanced = imbalance(contacts)
            epsilon = epsilon_of(contacts, self.obj)
            errors = (
                comparison.position_err_mm,
                comparison.orientation_err_deg,
                comparison.position_err_mm
                + comparison.orientation_err_deg
                + VF_COUNT_COST * count
                + STAGGER_COST * stagger
                + IMBALANCE_COST * unbalanced,
            )
        else:
            penalty += FEW_FINGERS_COST
        result = replace(
            result,
            cost=errors[2] + penalty,
            position_err_mm=errors[0],
            orientation_err_deg=errors[1],
            refused="; ".join(refused) or None,
            unbalanced=unbalanced,
            epsilon=epsilon,
        )
        return result

    def with_preshape(self, preshape: HandPreshape) -> HandDescription:
        """The hand with `preshape` alone, mapped from the grasp, its delta the open
        fingertips' height over the palm (0 at least)."""
        hand = replace(
            self.hand, preshapes={preshape.name: preshape}, grasp_map={self.grasp: preshape.name}
        )
        delta = self.fingertip_height(preshape.open_q)
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

    def planned(self, evaluated: Evaluated) -> Evaluated:
        """The candidate scored where the planner puts the hand (its own table raise,
        reach alternatives and roll: what the held trial executes); refused when the
        planner refuses it."""
        from graspframe.strategy.planner import PlanningError, PlanningTarget, plan_grasp

        hand = self.with_preshape(evaluated.preshape)
        T_world_object = self.obj.T_world_standing()
        target = PlanningTarget(
            self.grasp, self.T_object_human_palm, T_world_object, hand, self.obj
        )
        try:
            plan = plan_grasp(target)
        except PlanningError as exc:
            return replace(evaluated, cost=math.inf, refused=f"the planner refuses it: {exc}")
        T_palm_goal = inv_T(plan.T_world_palm_goal) @ T_world_object
        return self.score(evaluated.preshape, evaluated.choice, T_palm_goal=T_palm_goal)

    def robust_cost(self, evaluated: Evaluated) -> float:
        """The worst objective with the object ROBUST_SHIFT off its place along each
        horizontal axis (an object a finger nudges while the hand closes: a grasp that
        only works where the object stands exactly is fragile) and with the hand where
        the planner puts it."""
        costs = [evaluated.cost, self.planned(evaluated).cost]
        for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            shifted = self.score(
                evaluated.preshape, evaluated.choice, (ROBUST_SHIFT * dx, ROBUST_SHIFT * dy)
            )
            costs.append(shifted.cost)
        return max(costs)

    def search(self) -> list[Evaluated]:
        """The coordinate search from each of up to STARTS thumb placings, each with the
        object where it sits best in the palm for that placing (a thumb turned into
        opposition needs the object elsewhere in the palm, and every step there alone
        is refused: the thumb in the object); every candidate evaluated, best first."""
        thumbs = self.thumb_values()
        starts = [thumbs[0], thumbs[len(thumbs) // 2], thumbs[-1]][:STARTS]
        for thumb in dict.fromkeys(starts):
            start = replace(self.initial(), thumb=thumb)
            centres = [replace(start, shift_x=x, shift_y=y) for x in SHIFTS_X for y in SHIFTS_Y]
            best = min((self.evaluate(c) for c in centres), key=lambda e: e.cost)
            for _ in range(PASSES):
                for axis in range(len(self.axes(best.choice))):
                    # each parameter varied about the best so far
                    for candidate in self.axes(best.choice)[axis]:
                        evaluated = self.evaluate(candidate)
                        if evaluated.cost < best.cost:
                            best = evaluated
        return sorted(self.cache.values(), key=lambda e: e.cost)


def Rz(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
