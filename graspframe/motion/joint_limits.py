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

from graspframe.hal.descriptions import JointSpec
from graspframe.model_files.urdf_model import UrdfModel

TOLERANCE_DEG = 2.0  # [deg] a revolute joint past its limit by more than this is reported
TOLERANCE_MM = 2.0  # [mm] ... a prismatic joint
MM_PER_M = 1000.0


def model_joint_limits(model: UrdfModel) -> dict[str, JointSpec]:
    """The limits of every revolute and prismatic joint of the model, by name, as its URDF
    text declares them (continuous and fixed joints have none); a motion limit the file
    leaves out is infinite."""
    limits = {}
    for joint in model.root().iter("joint"):
        kind = joint.get("type")
        element = joint.find("limit")
        if kind not in ("revolute", "prismatic") or element is None:
            continue
        name = joint.get("name", "")
        limits[name] = JointSpec(
            name,
            float(element.get("lower", 0.0)),
            float(element.get("upper", 0.0)),
            max_velocity=float(element.get("velocity", math.inf)),
            max_effort=float(element.get("effort", math.inf)),
        )
    return limits


def prismatic_joints(model: UrdfModel) -> frozenset[str]:
    """The names of the model's prismatic joints (their positions are in [m])."""
    return frozenset(
        joint.get("name", "")
        for joint in model.root().iter("joint")
        if joint.get("type") == "prismatic"
    )


@dataclass(frozen=True)
class LimitExcess:
    """A joint's largest excess past its model limit in a run.

    excess, position: [rad] ([m] for a prismatic joint) past the limit, and the joint's
    position then; limit: the model's (a `JointSpec` of the model file's <limit>);
    sim_time: [s] when; stage: the last execution event before it (the stage the grasp was
    in, e.g. "execute.closed": the hold); prismatic: the joint slides (its values in [m]).
    """

    limit: JointSpec
    excess: float
    position: float
    sim_time: float
    stage: str
    prismatic: bool = False

    @property
    def joint(self) -> str:
        return self.limit.name

    @property
    def over_tolerance(self) -> bool:
        """Past the limit by more than the tolerance (TOLERANCE_DEG, TOLERANCE_MM)."""
        if self.prismatic:
            return self.excess * MM_PER_M > TOLERANCE_MM
        return math.degrees(self.excess) > TOLERANCE_DEG

    def _shown(self, value: float) -> float:
        """A value of this joint in the unit shown: [mm] when prismatic, else [deg]."""
        return value * MM_PER_M if self.prismatic else math.degrees(value)

    @property
    def unit(self) -> str:
        return "mm" if self.prismatic else "deg"

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

        def motion_limit(key: str) -> float:  # an infinite limit is kept as null
            value = limit.get(key)
            return math.inf if value is None else float(value)

        return cls(
            JointSpec(
                str(limit.get("name", limit.get("joint"))),  # "joint": an older entry's
                float(limit["lower"]),
                float(limit["upper"]),
                motion_limit("max_velocity"),
                motion_limit("max_effort"),
            ),
            float(data["excess"]),
            float(data["position"]),
            float(data["sim_time"]),
            str(data["stage"]),
            bool(data.get("prismatic", limit.get("prismatic", False))),
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
            (math.degrees(e.excess) for e in self.excesses if not e.prismatic),
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
        self.prismatic = prismatic_joints(model)
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
            prismatic = name in self.prismatic
            larger = LimitExcess(limit, excess, position, sim_time, self.stage, prismatic)
            if larger.over_tolerance and not (kept is not None and kept.over_tolerance):
                newly_over.append(larger)
            self._largest[name] = larger
        return newly_over

    def report(self) -> JointLimitReport:
        """Every joint that passed its limit so far, largest excess first."""
        ordered = sorted(self._largest.values(), key=lambda e: (e.prismatic, -e.excess))
        return JointLimitReport(tuple(ordered))
