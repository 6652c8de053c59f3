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
- Alternatives for a collision-free arm path (graspframe/strategy/arm_path.py): the
  grasp may be turned about the object's vertical axis when the object is symmetric
  about it (yaw), moved up along an upright object's axis (raise), and the via pose may
  be higher; all of them again with the hand on each adapter it declares (mounting: the
  palm pose is the same, the arm holds the hand differently).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from graspframe.errors import GraspframeError
from graspframe.grasps import HumanGrasp
from graspframe.hal.descriptions import HandDescription, HandPreshape
from graspframe.hal.objects import ObjectDescription
from graspframe.strategy.hand_geometry import closing_configurations, lowest_hand_point
from graspframe.transforms import as_pose, inv_T, make_T

MAX_RAISE_ITERATIONS = 5
RAISE_TOLERANCE = 1e-6  # [m]
DOWN = np.array([0.0, 0.0, -1.0])


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
    grasp: HumanGrasp,
    T_object_human_palm: NDArray[np.float64],
    T_world_object_est: NDArray[np.float64],
    hand: HandDescription,
    obj: ObjectDescription,
    table_height: float = 0.0,
    params: PlannerParams | None = None,
    variant: Variant | None = None,
) -> GraspPlan:
    """Plan the robot grasp (preshape, approach, goals; see the module docstring).

    table_height: [m] world height of the table top.
    variant: an alternative of the grasp (default: none).
    """
    params = params or PlannerParams()
    variant = variant or Variant()
    T_object_human_palm = as_pose(T_object_human_palm, "T_object_human_palm")
    T_world_object_est = as_pose(T_world_object_est, "T_world_object_est")
    if not params.pre_approach_distance > 0:
        raise PlanningError("pre_approach_distance must be > 0 [m]")
    if variant.yaw_deg and not obj.symmetric_about_z:
        raise PlanningError(f"a {obj.shape} is not symmetric about its axis: no yaw variant")
    preshape = hand.preshape_for(grasp)
    volar = grasp.volar_for_robot

    R_object_symmetry = _Rz(math.radians(variant.yaw_deg))
    R_object_palm = R_object_symmetry @ T_object_human_palm[:3, :3] @ _Rz(preshape.roll)
    p_palm_object = object_in_palm(preshape, obj, R_object_palm, volar, params.palm_clearance)
    volar_gap = p_palm_object[2] - obj.extent_along(-R_object_palm[:, 2]) if volar else 0.0
    if variant.raise_along_axis:
        # The hand higher up the object = the object lower in the palm frame.
        p_palm_object = p_palm_object - variant.raise_along_axis * (R_object_palm.T @ [0, 0, 1])
    T_object_palm = make_T(R_object_palm, -R_object_palm @ p_palm_object)
    T_goal = T_world_object_est @ T_object_palm
    approach, a = approach_direction(T_goal[:3, :3], params)

    # Raising the goal moves the object in the palm frame, and with it where the fingers
    # stop on it: repeat until the lowest point of the closing hand settles.
    table_raise = 0.0
    for _ in range(MAX_RAISE_ITERATIONS):
        configurations = closing_configurations(hand, preshape, obj, inv_T(T_object_palm))
        lowest = lowest_hand_point(hand, configurations, T_goal[:3, :3])
        min_goal_height = table_height + params.table_clearance - lowest
        step = max(0.0, min_goal_height - T_goal[2, 3])
        T_goal[2, 3] += step
        table_raise += step
        T_object_palm = inv_T(T_world_object_est) @ T_goal
        if step < RAISE_TOLERANCE:
            break
    T_pre = T_goal.copy()
    T_pre[:3, 3] -= params.pre_approach_distance * a
    T_via = T_pre.copy()
    if approach == "side":
        T_via[2, 3] += params.side_via_rise if variant.via_rise is None else variant.via_rise
    return GraspPlan(
        hand=hand.name,
        grasp=grasp,
        preshape=preshape.name,
        volar=volar,
        approach=approach,
        a_world=a,
        T_object_human_palm=T_object_human_palm,
        T_object_palm=T_object_palm,
        p_palm_object=inv_T(T_object_palm)[:3, 3],
        T_world_object_est=T_world_object_est,
        T_world_palm_goal=T_goal,
        T_world_palm_pre=T_pre,
        T_world_palm_via=T_via,
        standoff=float(inv_T(T_object_palm)[2, 3]),
        table_raise=table_raise,
        min_goal_height=min_goal_height,
        variant=variant,
        R_object_symmetry=R_object_symmetry,
        volar_gap=float(volar_gap),
    )


def _Rz(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
