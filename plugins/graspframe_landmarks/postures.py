"""The human model's grasp postures as landmark points and angle features.

Each grasp's posture of the human hand model (the registered hand `human`, asked of the
registry: open_q, closed_q [rad]) is sampled at closures 0..1 (q = open + closure
(closed - open), DIPs at 2/3 of their PIP) and placed by forward kinematics of the
model's URDF. The landmark-equivalent points (MediaPipe's layout, see features.py) are
frame origins in the model's root frame hh_wrist [m]: the wrist, the thumb's CMC
(hh_thumb_cmc_abd), MCP, IP joints and tip marker, and per finger its MCP, PIP, DIP
joints and tip marker (hh_<digit>_tip).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.grasps import HumanGrasp
from graspframe.robot_models.model import model_of
from graspframe_landmarks.features import angle_features

HUMAN_HAND = "human"  # the registered hand whose postures are the database
CLOSURES = np.linspace(0.0, 1.0, 21)  # [-] 0 open posture, 1 closed posture
LANDMARK_FRAMES = (
    "hh_wrist",
    "hh_thumb_cmc_abd",
    "hh_thumb_mcp",
    "hh_thumb_ip",
    "hh_thumb_tip",
    *(
        f"hh_{finger}_{part}"
        for finger in ("index", "middle", "ring", "little")
        for part in ("mcp", "pip", "dip", "tip")
    ),
)


@dataclass(frozen=True)
class PostureTable:
    """The sampled postures: `features` (N, 19) [rad], `grasps` (N,) indices into
    GRASP_ORDER, `R_wrist_palm` the model's palm frame in hh_wrist."""

    features: NDArray[np.float64]
    grasps: NDArray[np.int64]
    R_wrist_palm: NDArray[np.float64]


GRASP_ORDER = tuple(HumanGrasp)


class HumanModelLandmarks:
    """Forward kinematics of the human hand model to landmark-equivalent points."""

    def __init__(self) -> None:
        from graspframe.plugin_system.registry import get_hand
        from graspframe.robot_models.model import CollisionModel

        self.hand = get_hand(HUMAN_HAND)
        self.model = CollisionModel(model_of(self.hand))

    def posture(self, grasp: HumanGrasp, closure: float) -> dict[str, float]:
        """Joint positions [rad] at `closure` between the grasp's open and closed q."""
        preshape = self.hand.preshape_for(grasp)
        return {
            name: (1 - closure) * preshape.open_q[name] + closure * preshape.closed_q[name]
            for name in preshape.open_q
        }

    def points(self, q_by_joint: dict[str, float]) -> NDArray[np.float64]:
        """(21, 3) landmark-equivalent points [m] in hh_wrist for joint positions [rad]."""
        self.model.place(self.hand.with_model_followers(q_by_joint))
        return np.array([self.model.T_root_frame(f)[:3, 3] for f in LANDMARK_FRAMES])

    def R_wrist_palm(self) -> NDArray[np.float64]:
        return self.model.T_root_frame(self.hand.palm_frame)[:3, :3]


@functools.cache
def posture_table() -> PostureTable:
    """Every grasp's postures at CLOSURES, as angle features (built once per process)."""
    kinematics = HumanModelLandmarks()
    features, grasps = [], []
    for index, grasp in enumerate(GRASP_ORDER):
        for closure in CLOSURES:
            features.append(angle_features(kinematics.points(kinematics.posture(grasp, closure))))
            grasps.append(index)
    return PostureTable(np.array(features), np.array(grasps), kinematics.R_wrist_palm())
