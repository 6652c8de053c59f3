"""Watching the simulator keep the model's joint limits.

A physics engine holds a joint limit as one more constraint, solved iteratively together
with the contacts: a contact that pushes harder than the limit can hold (a hand driven
into the table with a finger under it) moves the joint past it. `JointLimitMonitor`
compares the measured position of every joint of the mounted robot (the arm's, the
hand's and its <mimic> followers') with the limits of the model's URDF text (what the
simulator is given) every control cycle, and keeps each joint's largest excess; a run
reports the joints past their limit by more than TOLERANCE_DEG (TOLERANCE_MM for a
prismatic joint) in result.json and in its summary.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from graspframe.model_files.urdf_model import UrdfModel

TOLERANCE_DEG = 2.0  # [deg] a revolute joint past its limit by more than this is reported
TOLERANCE_MM = 2.0  # [mm] ... a prismatic joint
MM_PER_M = 1000.0


@dataclass(frozen=True)
class JointLimit:
    """A joint's position limits in the model: lower, upper [rad] ([m] when prismatic)."""

    joint: str
    lower: float
    upper: float
    prismatic: bool

    def excess(self, position: float) -> float:
        """[rad] ([m]) past the nearer limit; 0 within them."""
        return max(self.lower - position, position - self.upper, 0.0)


def model_joint_limits(model: UrdfModel) -> dict[str, JointLimit]:
    """The limits of every revolute and prismatic joint of the model, by name, as its URDF
    text declares them (continuous and fixed joints have none)."""
    limits = {}
    for joint in model.root().iter("joint"):
        kind = joint.get("type")
        element = joint.find("limit")
        if kind not in ("revolute", "prismatic") or element is None:
            continue
        name = joint.get("name", "")
        lower, upper = float(element.get("lower", 0.0)), float(element.get("upper", 0.0))
        limits[name] = JointLimit(name, lower, upper, prismatic=kind == "prismatic")
    return limits


@dataclass(frozen=True)
class LimitExcess:
    """A joint's largest excess past its model limit in a run.

    excess, position: [rad] ([m] for a prismatic joint) past the limit, and the joint's
    position then; limit: the model's; sim_time: [s] when; stage: the last execution
    event before it (the stage the grasp was in, e.g. "execute.closed": the hold).
    """

    limit: JointLimit
    excess: float
    position: float
    sim_time: float
    stage: str

    @property
    def joint(self) -> str:
        return self.limit.joint

    @property
    def over_tolerance(self) -> bool:
        """Past the limit by more than the tolerance (TOLERANCE_DEG, TOLERANCE_MM)."""
        if self.limit.prismatic:
            return self.excess * MM_PER_M > TOLERANCE_MM
        return math.degrees(self.excess) > TOLERANCE_DEG

    def _shown(self, value: float) -> float:
        """A value of this joint in the unit shown: [mm] when prismatic, else [deg]."""
        return value * MM_PER_M if self.limit.prismatic else math.degrees(value)

    @property
    def unit(self) -> str:
        return "mm" if self.limit.prismatic else "deg"

    @property
    def excess_shown(self) -> float:
        """The excess in `unit`: [deg], or [mm] for a prismatic joint."""
        return self._shown(self.excess)

    def to_dict(self) -> dict[str, Any]:
        """The excess, the position and the limits in deg (mm for a prismatic joint)."""
        unit = self.unit
        return {
            "joint": self.joint,
            f"excess_{unit}": self._shown(self.excess),
            f"position_{unit}": self._shown(self.position),
            f"lower_{unit}": self._shown(self.limit.lower),
            f"upper_{unit}": self._shown(self.limit.upper),
            "sim_time": self.sim_time,
            "stage": self.stage,
        }

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> LimitExcess:
        """The excess from its JSON values (graspframe.common.json_files.jsonable of one: every
        field, in [rad] and [m]), as a cached human reference keeps it."""
        limit = data["limit"]
        return cls(
            JointLimit(
                str(limit["joint"]),
                float(limit["lower"]),
                float(limit["upper"]),
                bool(limit["prismatic"]),
            ),
            float(data["excess"]),
            float(data["position"]),
            float(data["sim_time"]),
            str(data["stage"]),
        )

    def describe(self) -> str:
        """One line, e.g. "hh_thumb_ip at -133.0 deg, 113.0 deg past its limits
        [-20.0, 80.0] at 1.56 s (after execute.closed)"."""
        unit = self.unit
        return (
            f"{self.joint} at {self._shown(self.position):.1f} {unit}, "
            f"{self._shown(self.excess):.1f} {unit} past its limits "
            f"[{self._shown(self.limit.lower):.1f}, {self._shown(self.limit.upper):.1f}] "
            f"at {self.sim_time:.2f} s (after {self.stage})"
        )


@dataclass(frozen=True)
class JointLimitReport:
    """What the monitor saw in a run: every joint that passed its limit at all, largest
    excess first (in deg, prismatic joints in mm after the revolute ones)."""

    excesses: tuple[LimitExcess, ...] = ()

    @property
    def violations(self) -> tuple[LimitExcess, ...]:
        """The joints past their limit by more than the tolerance."""
        return tuple(e for e in self.excesses if e.over_tolerance)

    @property
    def largest_excess_deg(self) -> float:
        """[deg] the largest excess of a revolute joint (0 when every one kept its limits)."""
        return max(
            (math.degrees(e.excess) for e in self.excesses if not e.limit.prismatic),
            default=0.0,
        )

    def to_json(self) -> dict[str, Any]:
        """result.json's "joint_limits"."""
        return {
            "tolerance_deg": TOLERANCE_DEG,
            "tolerance_mm": TOLERANCE_MM,
            "largest_excess_deg": self.largest_excess_deg,
            "violations": [e.to_dict() for e in self.violations],
            "excesses": [e.to_dict() for e in self.excesses],
        }


class JointLimitMonitor:
    """Each joint's largest excess past the model's limits, from the positions measured
    every control cycle (`check`). It only reads: the physics is not changed.

    stage: the stage the grasp is in, set by whoever runs it (the last event emitted).
    """

    def __init__(self, model: UrdfModel) -> None:
        self.limits = model_joint_limits(model)
        self.stage = "start"
        self._largest: dict[str, LimitExcess] = {}

    def check(self, sim_time: float, q_by_joint: Mapping[str, float]) -> list[LimitExcess]:
        """Compare measured positions [rad] ([m]) by joint name with the limits; returns the
        joints that have just passed their limit by more than the tolerance for the first
        time in the run. Joints the model does not limit are ignored."""
        newly_over = []
        for name, position in q_by_joint.items():
            limit = self.limits.get(name)
            if limit is None:
                continue
            excess = limit.excess(position)
            kept = self._largest.get(name)
            if excess <= 0.0 or (kept is not None and excess <= kept.excess):
                continue
            larger = LimitExcess(limit, excess, position, sim_time, self.stage)
            if larger.over_tolerance and not (kept is not None and kept.over_tolerance):
                newly_over.append(larger)
            self._largest[name] = larger
        return newly_over

    def report(self) -> JointLimitReport:
        """Every joint that passed its limit so far, largest excess first."""
        ordered = sorted(self._largest.values(), key=lambda e: (e.limit.prismatic, -e.excess))
        return JointLimitReport(tuple(ordered))
