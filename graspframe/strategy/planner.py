"""The planner: from a human grasp relative to the object to a robot grasp plan.

METHOD.md sections 3 and 4, backend-agnostic. Inputs: the human grasp type and palm pose
relative to the object (T_object_hand, from the image and the demonstration scene, or a
reference placement), the robot's belief of the object pose (T_world_object_est, which
may be wrong), and the hand description. Output: a plain, serialisable GraspPlan.

Choices the method leaves open (see docs/method.md):
- Approach selection: the palm is "oriented like the human Small Diameter grasp" when its
  normal is within SIDE_APPROACH_MAX_TILT_DEG of horizontal and its y axis (across the
  palm) within the same angle of vertical: then the side approach a_s (the palm normal
  projected on the table plane), otherwise the top approach a_v (straight down).
- The robot palm takes the human palm orientation relative to the object (the palm
  frames of all hands share one convention).
- Volar grasps (Large and Small Diameter) aim the palm at the human palm position
  p_h->o. Non-volar grasps aim at the human grasp point (where the human's fingers hold
  the object) and stop where the robot preshape's grasp centre lands on it. With the
  default grasp centre (0, 0, delta) and the palm normal along a, this is METHOD's
  "p_h->o minus delta" along the approach; hands whose fingers close forward of the palm
  centre declare their grasp centre.
- A top grasp never drives the fingers into the table: the goal is raised until the
  fingers' closing sweep depth stays TABLE_CLEARANCE above the table top. A non-volar top
  grasp (no feedback) never drives the palm into the object either: the goal stays
  PALM_CLEARANCE above the top of the object where the robot believes it is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.errors import GraspframeError
from graspframe.grasps import HumanGrasp
from graspframe.hal.descriptions import HandDescription
from graspframe.strategy.hand_geometry import closing_sweep_depth
from graspframe.transforms import as_pose

SIDE_APPROACH_MAX_TILT_DEG = 30.0
PRE_APPROACH_DISTANCE = 0.10  # [m] the approach starts this far before the goal
# A side approach reaches its pre-approach pose by coming straight down from this much
# higher, so the open hand does not sweep through the object on its way there.
SIDE_VIA_RISE = 0.15  # [m]
# Top grasps keep the deepest reach of the closing fingers this far above the table.
TABLE_CLEARANCE = 0.01  # [m]
PALM_CLEARANCE = 0.005  # [m] of a non-volar palm goal above the believed object top
DOWN = np.array([0.0, 0.0, -1.0])


@dataclass(frozen=True)
class PlannerParams:
    """side_approach_max_tilt_deg: threshold of the approach selection [deg];
    pre_approach_distance: start of the approach before the goal along a [m];
    side_via_rise: height of the via pose above a side pre-approach pose [m];
    table_clearance: of the closing fingers above the table in a top grasp [m]."""

    side_approach_max_tilt_deg: float = SIDE_APPROACH_MAX_TILT_DEG
    pre_approach_distance: float = PRE_APPROACH_DISTANCE
    side_via_rise: float = SIDE_VIA_RISE
    table_clearance: float = TABLE_CLEARANCE


@dataclass(frozen=True)
class GraspPlan:
    """A robot grasp to execute, in the world frame of the robot's belief.

    approach: "side" or "top"; a_world: unit approach direction.
    T_world_palm_goal: volar: where the palm should touch; non-volar: where it stops.
    T_world_palm_pre: start of the approach (goal - pre_approach_distance * a).
    T_world_palm_via: reached first; the palm then moves straight to the pre-approach
        pose (equal to it for a top approach).
    standoff: [m] delta used for a non-volar goal (0 for volar).
    table_raise: [m] how far the goal was raised to keep the fingers off the table and
        the palm off the object.
    """

    hand: str
    grasp: HumanGrasp
    preshape: str
    volar: bool
    approach: str
    a_world: NDArray[np.float64]
    T_object_hand: NDArray[np.float64]
    T_world_object_est: NDArray[np.float64]
    T_world_palm_goal: NDArray[np.float64]
    T_world_palm_pre: NDArray[np.float64]
    T_world_palm_via: NDArray[np.float64]
    standoff: float
    table_raise: float = 0.0

    @property
    def pre_approach_distance(self) -> float:
        """[m] from the pre-approach pose to the goal along a."""
        return float(np.linalg.norm(self.T_world_palm_goal[:3, 3] - self.T_world_palm_pre[:3, 3]))

    def to_dict(self) -> dict:
        return {
            "hand": self.hand,
            "grasp": self.grasp.value,
            "preshape": self.preshape,
            "volar": self.volar,
            "approach": self.approach,
            "a_world": self.a_world.tolist(),
            "T_object_hand": self.T_object_hand.tolist(),
            "T_world_object_est": self.T_world_object_est.tolist(),
            "T_world_palm_goal": self.T_world_palm_goal.tolist(),
            "T_world_palm_pre": self.T_world_palm_pre.tolist(),
            "T_world_palm_via": self.T_world_palm_via.tolist(),
            "standoff": self.standoff,
            "table_raise": self.table_raise,
        }


def is_side_orientation(R_world_palm: NDArray[np.float64], max_tilt_deg: float) -> bool:
    """True when the palm is oriented like a human Small Diameter grasp: its normal
    (palm z) near horizontal and the axis across the palm (palm y) near vertical."""
    z_palm, y_palm = R_world_palm[:, 2], R_world_palm[:, 1]
    normal_tilt = math.degrees(math.asin(min(1.0, abs(z_palm[2]))))
    y_from_vertical = math.degrees(math.acos(min(1.0, abs(y_palm[2]))))
    return normal_tilt <= max_tilt_deg and y_from_vertical <= max_tilt_deg


def approach_direction(
    R_world_palm: NDArray[np.float64], params: PlannerParams
) -> tuple[str, NDArray[np.float64]]:
    """("side", a_s) along the palm normal in the table plane, or ("top", a_v) down."""
    if is_side_orientation(R_world_palm, params.side_approach_max_tilt_deg):
        a = R_world_palm[:, 2].copy()
        a[2] = 0.0
        return "side", a / np.linalg.norm(a)
    return "top", DOWN.copy()


def plan_grasp(
    grasp: HumanGrasp,
    T_object_hand: NDArray[np.float64],
    T_world_object_est: NDArray[np.float64],
    hand: HandDescription,
    p_hand_grasp: NDArray[np.float64] | None = None,
    table_height: float = 0.0,
    object_top_height: float | None = None,
    params: PlannerParams | None = None,
) -> GraspPlan:
    """Plan the robot grasp (METHOD.md 4.1-4.3, goals of 4.4 and 4.5).

    p_hand_grasp: [m] the human grasp point in the human palm frame (where the object
        sits in the human's hand); None: on the palm normal at the human palm.
    table_height: [m] world height of the table top.
    object_top_height: [m] world height of the top of the object as believed (None:
        unknown, no palm clamp).
    """
    params = params or PlannerParams()
    T_object_hand = as_pose(T_object_hand, "T_object_hand")
    T_world_object_est = as_pose(T_world_object_est, "T_world_object_est")
    if not params.pre_approach_distance > 0:
        raise GraspframeError("pre_approach_distance must be > 0 [m]")
    preshape = hand.preshape_for(grasp)
    T_world_hand = T_world_object_est @ T_object_hand
    approach, a = approach_direction(T_world_hand[:3, :3], params)
    volar = grasp.volar_for_robot

    T_goal = T_world_hand.copy()
    standoff = 0.0
    if not volar:
        p_hand = np.zeros(3) if p_hand_grasp is None else np.asarray(p_hand_grasp, dtype=float)
        p_world_grasp = T_world_hand[:3, :3] @ p_hand + T_world_hand[:3, 3]
        robot_center = np.asarray(preshape.grasp_center_palm, dtype=float)
        T_goal[:3, 3] = p_world_grasp - T_world_hand[:3, :3] @ robot_center
        standoff = float(robot_center[2])
    table_raise = 0.0
    if approach == "top":
        lowest = table_height + closing_sweep_depth(hand, preshape.name) + params.table_clearance
        if not volar and object_top_height is not None:
            lowest = max(lowest, object_top_height + PALM_CLEARANCE)
        table_raise = max(0.0, lowest - T_goal[2, 3])
        T_goal[2, 3] += table_raise
    T_pre = T_goal.copy()
    T_pre[:3, 3] -= params.pre_approach_distance * a
    T_via = T_pre.copy()
    if approach == "side":
        T_via[2, 3] += params.side_via_rise
    return GraspPlan(
        hand=hand.name,
        grasp=grasp,
        preshape=preshape.name,
        volar=volar,
        approach=approach,
        a_world=a,
        T_object_hand=T_object_hand,
        T_world_object_est=T_world_object_est,
        T_world_palm_goal=T_goal,
        T_world_palm_pre=T_pre,
        T_world_palm_via=T_via,
        standoff=standoff,
        table_raise=table_raise,
    )
