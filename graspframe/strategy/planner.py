"""The planner: from a human grasp relative to the object to a robot grasp plan.

The method's steps 3 and 4 (docs/method.md#the-grasp-strategy), backend-agnostic.
Inputs: the human grasp type and palm pose relative to the object (T_object_human_palm,
from the image and the demonstration scene, or a reference placement), the robot's
belief of the object pose (T_world_object_est, which may be wrong), the object and the
hand description. Output: a plain, serialisable GraspPlan.

Choices the method leaves open (see docs/method.md; the settings in quotes are
`PlannerParams` fields):
- The robot palm takes the human palm orientation relative to the object (the palm
  frames of all hands share one convention), turned by the preshape's preferred roll
  about the palm normal.
- The object goes where the robot hand holds it: the preshape's grasp centre in the palm
  frame (its design object's centre), with the height along the palm normal set by the
  real object's extent: a volar grasp rests the object on the palm; a non-volar grasp
  keeps the object's near face where the design object's was, never closer to the palm
  than `palm_clearance`. With the default grasp centre (0, 0, delta) this is the method's
  "p_h->o minus delta" along the approach. A preshape with a stop_direction (fingers
  that take the object's rim where they stand) also keeps the object's extent along it
  where the design object's was, so a larger object sits further back from them.
- Approach selection follows the palm normal: within `side_approach_max_tilt_deg` of
  horizontal, the side approach a_s (the normal projected on the table plane); pointing
  further down, the top approach a_v (straight down). A palm facing up cannot be
  approached from below the table and is refused.
- The whole hand stays `table_clearance` above the table at the goal: every shape of the
  hand (palm included), in the goal orientation, over the closing motion (each finger
  stopping at the object), sets the lowest allowed palm height; the goal is raised to it
  and the volar correction loop never goes below it.
- When that raise lifts the fingers off the object (a long thumb over a thin disc: the
  kinematic closing at the raised goal brings fewer than two real fingers onto it, and
  fewer than it would with no table in the way), the planner tries the ways that keep
  them on it, in order (`REACH_ALTERNATIVES`, `Reach`): a lower goal with only the
  fingertips nearer the table (`fingertip_clearance`, as a person's come down to the
  table under a thin object), the palm tilted by 15 or 30 deg about its x or y axis
  (the long finger's side up), then rolled about its normal by 90, 180 or 270 deg (the
  long finger on the far side). The first that brings every finger the closing would
  bring with no table in the way onto the object, its open hand at the goal clear of
  the object (so the approach does not push it), is planned (`GraspPlan.reach` says
  which: the lowest of its first touches above the object's centroid is
  `lowest_touch_height`); when none does, the grasp is refused in one line: the link that sets the
  raise, how far below the palm it reaches, how far the hand was raised and how tall
  the object is.
- Alternatives for a collision-free arm path (graspframe/strategy/arm_path.py): the
  grasp may be turned about the object's vertical axis when the object is symmetric
  about it (yaw), moved up along an upright object's axis (raise), and the via pose may
  be higher; all of them again with the hand on each adapter it declares (mounting: the
  palm pose is the same, the arm holds the hand differently).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from graspframe.common.defaults import TABLE_HEIGHT
from graspframe.common.errors import GraspframeError
from graspframe.common.grasps import PALM, HumanGrasp
from graspframe.common.transforms import as_pose, inv_T, make_T
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.objects import ObjectDescription
from graspframe.strategy.hand_geometry import closing_sweep, fingertip_links, lowest_points

MAX_RAISE_ITERATIONS = 5
RAISE_TOLERANCE = 1e-6  # [m]
DOWN = np.array([0.0, 0.0, -1.0])


@dataclass(frozen=True, eq=False)
class PlanningTarget:
    """What every planner and path check plans for, as one value: the human grasp, the
    human palm in the object frame (T_object_human_palm [m]), where the robot believes
    the object is (T_world_object_est [m]), the hand, the object and the table top's
    world height (table_height [m]). The poses are checked on creation."""

    grasp: HumanGrasp
    T_object_human_palm: NDArray[np.float64]
    T_world_object_est: NDArray[np.float64]
    hand: HandDescription
    obj: ObjectDescription
    table_height: float = TABLE_HEIGHT

    def __post_init__(self) -> None:
        for name in ("T_object_human_palm", "T_world_object_est"):
            object.__setattr__(self, name, as_pose(getattr(self, name), name))


class PlanningError(GraspframeError):
    """No plan satisfies the constraints; the message says which and why."""


@dataclass(frozen=True)
class PlannerParams:
    """The planner's settings, each written here only."""

    # A palm normal within this of horizontal gives the side approach.
    side_approach_max_tilt_deg: float = 30.0  # [deg]
    # The approach starts this far before the goal along a: more than the open fingers
    # reach plus the 5 cm object error of experiment B.
    pre_approach_distance: float = 0.15  # [m]
    # A side approach reaches its pre-approach pose by coming straight down from this
    # much higher, so the open hand does not sweep through the object on its way there.
    side_via_rise: float = 0.15  # [m]
    table_clearance: float = 0.01  # [m] of the whole hand above the table at the goal
    # [m] of the fingertips alone when only they may come nearer (`Reach`): just over the
    # 5 mm the path check keeps every link from the table (arm_path.py).
    fingertip_clearance: float = 0.006
    palm_clearance: float = 0.005  # [m] of a non-volar object's near face from the palm


@dataclass(frozen=True)
class Variant:
    """One alternative of the same grasp.

    yaw_deg: [deg] the grasp turned about the object's vertical axis (objects symmetric
        about it only: the grasp is the same grasp of the same object).
    raise_along_axis: [m] the object held this much lower in the hand, i.e. the hand
        higher up an upright object's axis.
    via_rise: [m] height of the via pose above a side pre-approach pose (None: the
        planner's default).
    mounting: the hand's mounting on the arm flange (a name in HandDescription.mountings).
    """

    yaw_deg: float = 0.0
    raise_along_axis: float = 0.0
    via_rise: float | None = None
    mounting: str | None = None


@dataclass(frozen=True)
class Reach:
    """A way of keeping the fingers on an object the table raise would lift them off.

    fingertips_lower: only the fingertips (each real finger's last shaped link) may
        come down to `fingertip_clearance` above the table; the rest of the hand stays
        `table_clearance` above it. tilt_axis, tilt_deg: the palm turned about its own
        x or y axis [deg]; roll_deg: turned about its normal [deg] (both about the grasp
        point).
    """

    fingertips_lower: bool = False
    tilt_axis: str = "y"
    tilt_deg: float = 0.0
    roll_deg: float = 0.0

    def describe(self) -> str:
        """In words; empty for the plan as the human grasp has it."""
        parts = []
        if self.fingertips_lower:
            parts.append("only the fingertips lower")
        if self.tilt_deg:
            parts.append(f"palm tilted {self.tilt_deg:+.0f} deg about its {self.tilt_axis}")
        if self.roll_deg:
            parts.append(f"palm rolled {self.roll_deg:+.0f} deg about its normal")
        return ", ".join(parts)

    def R_palm_turned(self) -> NDArray[np.float64]:
        """The turn of the palm frame (in the palm frame)."""
        tilt = math.radians(self.tilt_deg)
        R_tilt = _Rx(tilt) if self.tilt_axis == "x" else _Ry(tilt)
        return R_tilt @ _Rz(math.radians(self.roll_deg))


REACH_ALTERNATIVES = (
    Reach(fingertips_lower=True),
    *(
        Reach(fingertips_lower=True, tilt_axis=axis, tilt_deg=tilt)
        for axis in ("y", "x")
        for tilt in (15.0, -15.0, 30.0, -30.0)
    ),
    *(Reach(fingertips_lower=True, roll_deg=roll) for roll in (90.0, 180.0, 270.0)),
)
MIN_FINGERS_ON_OBJECT = 2  # real fingers on the object below which a raise is costly


@dataclass(frozen=True)
class GraspPlan:
    """A robot grasp to execute, in the world frame of the robot's belief.

    approach: "side" or "top"; a_world: unit approach direction.
    T_object_human_palm: the human palm pose the plan copies (object frame).
    T_object_palm: the robot palm at the goal (object frame of the robot's belief).
    p_palm_object: [m] where the object's centroid sits in the palm frame at the goal.
    T_world_palm_goal: volar: where the palm should touch; non-volar: where it stops.
    T_world_palm_pre: start of the approach (goal - pre_approach_distance * a).
    T_world_palm_via: reached first; the palm then moves straight to the pre-approach
        pose (equal to it for a top approach).
    standoff: [m] height of the object's centroid above the palm (p_palm_object z).
    volar_gap: [m] volar: how far the palm backs off the object it found before closing
        (the preshape's `volar_centre_height` for thin objects; 0: it closes touching).
    table_raise: [m] how far the goal was raised to keep the whole hand off the table.
    min_goal_height: [m] lowest world height of the palm origin that keeps the hand
        `table_clearance` above the table (the correction loop stays above it).
    R_object_symmetry: rotation of the object frame that the variant's yaw used (the
        object looks the same after it); the score turns robot contacts back by it.
    lowest_link: the hand link whose lowest point set `min_goal_height`;
        lowest_below_palm: [m] how far below the palm origin it reaches at the goal.
    reach: how the plan keeps the fingers on the object when the table raise would
        lift them off it (`Reach.describe`; empty: as the human grasp has it).
    fingers_on_object: the real fingers the kinematic closing at the goal brings onto
        the object; fingers_without_table: those it would bring with no table in the
        way (the goal not raised); open_inside_object: the hand links inside the object
        in the open posture at the goal (an approach that would push it);
        lowest_touch_height: [m] the lowest of the fingers' first touches above the
        object's centroid (object frame z, up as it rests; 0 without a touch).
    """

    hand: str
    grasp: HumanGrasp
    preshape: str
    volar: bool
    approach: str
    a_world: NDArray[np.float64]
    T_object_human_palm: NDArray[np.float64]
    T_object_palm: NDArray[np.float64]
    p_palm_object: NDArray[np.float64]
    T_world_object_est: NDArray[np.float64]
    T_world_palm_goal: NDArray[np.float64]
    T_world_palm_pre: NDArray[np.float64]
    T_world_palm_via: NDArray[np.float64]
    standoff: float
    table_raise: float
    min_goal_height: float
    variant: Variant = field(default_factory=Variant)
    R_object_symmetry: NDArray[np.float64] = field(default_factory=lambda: np.eye(3))
    volar_gap: float = 0.0
    lowest_link: str = ""
    lowest_below_palm: float = 0.0
    reach: str = ""
    fingers_on_object: tuple[str, ...] = ()
    fingers_without_table: tuple[str, ...] = ()
    open_inside_object: tuple[str, ...] = ()
    lowest_touch_height: float = 0.0

    @property
    def pre_approach_distance(self) -> float:
        """[m] from the pre-approach pose to the goal along a."""
        return float(np.linalg.norm(self.T_world_palm_goal[:3, 3] - self.T_world_palm_pre[:3, 3]))


def approach_direction(
    R_world_palm: NDArray[np.float64], params: PlannerParams
) -> tuple[str, NDArray[np.float64]]:
    """("side", a_s) along the palm normal in the table plane when the normal is within
    the threshold of horizontal, ("top", a_v) straight down when it points further down.
    A palm facing up (normal above the threshold) raises PlanningError."""
    z_palm = R_world_palm[:, 2]
    limit = math.sin(math.radians(params.side_approach_max_tilt_deg))
    if z_palm[2] < -limit:
        return "top", DOWN.copy()
    if z_palm[2] > limit:
        tilt = math.degrees(math.asin(min(1.0, z_palm[2])))
        raise PlanningError(
            f"the palm faces up ({tilt:.0f} deg above horizontal): no approach from below "
            f"the table; side grasps accept up to {params.side_approach_max_tilt_deg:.0f} deg"
        )
    a = z_palm.copy()
    a[2] = 0.0
    return "side", a / np.linalg.norm(a)


def object_in_palm(
    preshape: HandPreshape,
    obj: ObjectDescription,
    R_object_palm: NDArray[np.float64],
    volar: bool,
    palm_clearance: float = PlannerParams.palm_clearance,
) -> NDArray[np.float64]:
    """[m] where the object's centroid sits in the palm frame (see the module docstring)."""
    centre = np.array(preshape.grasp_center_palm, dtype=float)
    # The object's face towards the palm: its extent back along the palm normal.
    extent = obj.extent_along(-R_object_palm[:, 2])
    if volar:
        centre[2] = max(extent, preshape.volar_centre_height or 0.0)
        return centre
    design = preshape.design_object
    if design is not None:
        centre[2] += extent - design.extent_along((0.0, 0.0, 1.0))
        if preshape.stop_direction is not None:
            u = np.asarray(preshape.stop_direction, dtype=float)
            u = u / np.linalg.norm(u)
            centre -= (obj.extent_along(R_object_palm @ u) - design.extent_along(u)) * u
    centre[2] = max(centre[2], extent + palm_clearance)
    return centre


def plan_grasp(
    target: PlanningTarget, params: PlannerParams | None = None, variant: Variant | None = None
) -> GraspPlan:
    """Plan the robot grasp for `target` (preshape, approach, goals; see the module
    docstring). variant: an alternative of the grasp (default: none)."""
    params = params or PlannerParams()
    variant = variant or Variant()
    grasp, hand, obj, table_height = target.grasp, target.hand, target.obj, target.table_height
    T_object_human_palm, T_world_object_est = target.T_object_human_palm, target.T_world_object_est
    if not params.pre_approach_distance > 0:
        raise PlanningError("pre_approach_distance must be > 0 [m]")
    if variant.yaw_deg and not obj.symmetric_about_z:
        raise PlanningError(f"a {obj.shape} is not symmetric about its axis: no yaw variant")
    preshape = hand.preshape_for(grasp)

    R_object_symmetry = _Rz(math.radians(variant.yaw_deg))
    R_object_palm = R_object_symmetry @ T_object_human_palm[:3, :3] @ _Rz(preshape.roll)
    goal = _GoalProblem(
        grasp, T_object_human_palm, T_world_object_est, hand, preshape, obj, table_height,
        params, variant, R_object_symmetry,
    )  # fmt: skip
    plan = goal.plan(R_object_palm, Reach())
    needed = min(MIN_FINGERS_ON_OBJECT, sum(f != PALM for f in hand.real_fingers))
    reached = len(plan.fingers_on_object)
    if reached >= needed or reached >= len(plan.fingers_without_table):
        return plan  # enough fingers reach the object, or the raise cost none
    for reach in REACH_ALTERNATIVES:
        try:
            alternative = goal.plan(R_object_palm @ reach.R_palm_turned(), reach)
        except PlanningError:
            continue  # turned so the palm faces up: no approach
        brings = set(alternative.fingers_on_object)
        if brings >= set(plan.fingers_without_table) and not alternative.open_inside_object:
            return alternative
    reaching = ", ".join(plan.fingers_on_object) or "no finger"
    raise PlanningError(
        f"keeping the {hand.name} hand {1000 * params.table_clearance:.0f} mm above the table "
        f"raises it {1000 * plan.table_raise:.0f} mm (its link {plan.lowest_link!r} reaches "
        f"{1000 * plan.lowest_below_palm:.0f} mm below the palm), where only {reaching} "
        f"reaches the {1000 * 2 * obj.half_height:.0f} mm tall {obj.name} (with no table in "
        f"the way: {', '.join(plan.fingers_without_table)}); neither a lower goal with only "
        "the fingertips nearer the table nor the palm tilted (15, 30 deg) or rolled (90, 180, "
        "270 deg) brings them all onto it"
    )


@dataclass(frozen=True)
class _GoalProblem:
    """One grasp goal to place: the values every palm orientation tried shares."""

    grasp: HumanGrasp
    T_object_human_palm: NDArray[np.float64]
    T_world_object_est: NDArray[np.float64]
    hand: HandDescription
    preshape: HandPreshape
    obj: ObjectDescription
    table_height: float
    params: PlannerParams
    variant: Variant
    R_object_symmetry: NDArray[np.float64]

    def plan(self, R_object_palm: NDArray[np.float64], reach: Reach) -> GraspPlan:
        """The plan with the palm at R_object_palm, raised off the table (with `reach`'s
        clearance rule)."""
        hand, preshape, obj, params = self.hand, self.preshape, self.obj, self.params
        volar = self.grasp.volar_for_robot
        p_palm_object = object_in_palm(preshape, obj, R_object_palm, volar, params.palm_clearance)
        volar_gap = p_palm_object[2] - obj.extent_along(-R_object_palm[:, 2]) if volar else 0.0
        if self.variant.raise_along_axis:
            # The hand higher up the object = the object lower in the palm frame.
            up_palm = R_object_palm.T @ [0, 0, 1]
            p_palm_object = p_palm_object - self.variant.raise_along_axis * up_palm
        T_object_palm = make_T(R_object_palm, -R_object_palm @ p_palm_object)
        T_goal = self.T_world_object_est @ T_object_palm
        approach, a = approach_direction(T_goal[:3, :3], params)
        clearance = _clearances(hand, params, reach.fingertips_lower)

        # Raising the goal moves the object in the palm frame, and with it where the
        # fingers stop on it: repeat until the lowest point of the closing hand settles.
        table_raise = 0.0
        unraised: tuple[str, ...] = ()
        for iteration in range(MAX_RAISE_ITERATIONS):
            sweep = closing_sweep(hand, preshape, obj, inv_T(T_object_palm))
            unraised = sweep.touched if iteration == 0 else unraised
            lowest = lowest_points(hand, sweep.configurations, T_goal[:3, :3])
            lowest_link = max(lowest, key=lambda link: clearance(link) - lowest[link])
            min_goal_height = self.table_height + clearance(lowest_link) - lowest[lowest_link]
            step = max(0.0, min_goal_height - T_goal[2, 3])
            T_goal[2, 3] += step
            table_raise += step
            T_object_palm = inv_T(self.T_world_object_est) @ T_goal
            if step < RAISE_TOLERANCE:
                break
        if table_raise > RAISE_TOLERANCE:  # where the fingers stop at the raised goal
            sweep = closing_sweep(hand, preshape, obj, inv_T(T_object_palm))
        T_pre = T_goal.copy()
        T_pre[:3, 3] -= params.pre_approach_distance * a
        T_via = T_pre.copy()
        if approach == "side":
            rise = params.side_via_rise if self.variant.via_rise is None else self.variant.via_rise
            T_via[2, 3] += rise
        return GraspPlan(
            hand=hand.name,
            grasp=self.grasp,
            preshape=preshape.name,
            volar=volar,
            approach=approach,
            a_world=a,
            T_object_human_palm=self.T_object_human_palm,
            T_object_palm=T_object_palm,
            p_palm_object=inv_T(T_object_palm)[:3, 3],
            T_world_object_est=self.T_world_object_est,
            T_world_palm_goal=T_goal,
            T_world_palm_pre=T_pre,
            T_world_palm_via=T_via,
            standoff=float(inv_T(T_object_palm)[2, 3]),
            table_raise=table_raise,
            min_goal_height=min_goal_height,
            variant=self.variant,
            R_object_symmetry=self.R_object_symmetry,
            volar_gap=float(volar_gap),
            lowest_link=lowest_link,
            lowest_below_palm=-float(lowest[lowest_link]),
            reach=reach.describe(),
            fingers_on_object=sweep.touched,
            fingers_without_table=unraised,
            open_inside_object=sweep.open_inside,
            lowest_touch_height=float(min(sweep.p_object_touch[:, 2], default=0.0)),
        )


def _clearances(
    hand: HandDescription, params: PlannerParams, fingertips_lower: bool
) -> Callable[[str], float]:
    """link -> [m] how far above the table it must stay at the goal."""
    tips = set(fingertip_links(hand).values()) if fingertips_lower else set()

    def clearance(link: str) -> float:
        return params.fingertip_clearance if link in tips else params.table_clearance

    return clearance


def _Rz(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _Rx(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _Ry(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
