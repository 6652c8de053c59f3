"""Virtual fingers: the method's grasp-similarity metric (docs/method.md, 5), on arrays.

A real finger is one finger or the palm; a virtual finger is a set of real fingers whose
forces act in unison. The steps, each a pure function:

1. `group_by_real_finger` (real_fingers.py): contacts (from any source) -> one
   `RealFingerContacts` per real finger, in a common frame (the object frame in practice).
2. to 4. cohesion.py: the force coupling of two real fingers, the cohesive index C_Vk of
   a virtual finger, the effective cohesion C_eff of a partition, and `best_partition`,
   the partition of the touching real fingers that maximises it.
5. `virtual_finger`: the pose of a virtual finger (mean contact position and normalised
   mean contact normal over its T(V_k) contacts).
6. `compare`: robot virtual fingers against the human's, matched one-to-one.

`virtual_fingers_from_contacts` runs steps 1 to 5 on one grasp's contacts.

Positions are in metres, forces in newtons, normals are unit vectors; errors reported in
millimetres and degrees carry the suffixes `_mm` and `_deg`. No simulator is imported.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import linear_sum_assignment

from graspframe.common.contacts import Contact
from graspframe.common.errors import GraspframeError, NoContactsError
from graspframe.common.json_files import jsonable
from graspframe.metrics.cohesion import Partition, best_partition, cohesive_index
from graspframe.metrics.real_fingers import RealFingerContacts, group_by_real_finger
from graspframe.metrics.vectors import (
    ZERO_FORCE,
    Vectors,
    checked_unit_vectors,
    checked_vectors,
)

MIN_MEAN_NORMAL = 1e-6
"""Length of the mean of unit normals below which a virtual finger has no orientation."""


@dataclass(frozen=True, eq=False)
class VirtualFinger:
    """A set of real fingers acting in unison, and its pose in the common frame.

    members: names of its real fingers (sorted).
    position: (3,) mean of all its contact positions [m].
    normal: (3,) mean of all its contact normals, normalised (unit).
    contact_count: T(V_k), the number of contacts averaged.
    cohesive_index: C_Vk of its real fingers' net forces [0..1].
    """

    members: tuple[str, ...]
    position: Vectors
    normal: Vectors
    contact_count: int
    cohesive_index: float

    def __post_init__(self) -> None:
        members = tuple(self.members)
        if not members or not all(isinstance(name, str) for name in members):
            raise GraspframeError(f"members must be real finger names, got {self.members!r}")
        position = checked_vectors(np.reshape(self.position, (1, -1)), f"position of {members}")[0]
        normal = checked_unit_vectors(np.reshape(self.normal, (1, -1)), f"normal of {members}")[0]
        if int(self.contact_count) < 1:
            raise GraspframeError(f"contact_count must be >= 1, got {self.contact_count}")
        if not 0.0 <= float(self.cohesive_index) <= 1.0:
            raise GraspframeError(f"cohesive_index must lie in [0, 1], got {self.cohesive_index}")
        object.__setattr__(self, "members", members)
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "normal", normal)


def virtual_finger(fingers: Sequence[RealFingerContacts]) -> VirtualFinger:
    """The virtual finger made of `fingers`: pose averaged over all their contacts.

    Every contact counts once, so a real finger with more contacts weighs more. Raises
    GraspframeError when the normals cancel out (mean length < MIN_MEAN_NORMAL): the
    virtual finger then has no orientation.
    """
    if not fingers:
        raise GraspframeError("a virtual finger needs at least one real finger")
    names = [f.name for f in fingers]
    if len(set(names)) != len(names):
        raise GraspframeError(f"real fingers must be distinct, got {names}")
    positions = np.concatenate([f.positions for f in fingers])
    normal = np.concatenate([f.normals for f in fingers]).mean(axis=0)
    length = float(np.linalg.norm(normal))
    if length < MIN_MEAN_NORMAL:
        raise GraspframeError(
            f"contact normals of virtual finger {sorted(names)} cancel out "
            f"(mean length {length:.3g}); its orientation is undefined"
        )
    return VirtualFinger(
        members=tuple(sorted(names)),
        position=positions.mean(axis=0),
        normal=normal / length,
        contact_count=len(positions),
        cohesive_index=cohesive_index([f.force for f in fingers]),
    )


@dataclass(frozen=True, eq=False)
class VirtualFingerGrasp:
    """The virtual-finger representation of one grasp (the best partition).

    virtual_fingers: one per block of `partition`, in the same order.
    partition: the chosen partition and its C_eff.
    ignored_real_fingers: real fingers that had contacts but a net force at or below
        `min_force`; they take no part (and count as not touching in `compare`).
    """

    virtual_fingers: tuple[VirtualFinger, ...]
    partition: Partition
    ignored_real_fingers: tuple[str, ...] = ()

    @property
    def count(self) -> int:
        return len(self.virtual_fingers)

    @property
    def c_eff(self) -> float:
        return self.partition.c_eff

    @property
    def touching_real_fingers(self) -> tuple[str, ...]:
        return tuple(sorted(name for block in self.partition.blocks for name in block))

    def to_dict(self) -> dict:
        return {
            "c_eff": self.c_eff,
            "virtual_fingers": [jsonable(vf) for vf in self.virtual_fingers],
            "ignored_real_fingers": list(self.ignored_real_fingers),
        }


def virtual_fingers_from_real_fingers(
    fingers: Iterable[RealFingerContacts], *, min_force: float = 0.0
) -> VirtualFingerGrasp:
    """The best virtual-finger representation of real fingers' contacts (any source).

    min_force: [N] real fingers whose net force magnitude is at or below this (and below
        ZERO_FORCE in any case) have no force direction; they are listed in
        `ignored_real_fingers` instead of being partitioned.
    Raises NoContactsError when no real finger is left.
    """
    if not (math.isfinite(min_force) and min_force >= 0.0):
        raise GraspframeError(f"min_force must be a finite force >= 0 [N], got {min_force}")
    fingers = list(fingers)
    names = [f.name for f in fingers]
    if len(set(names)) != len(names):
        raise GraspframeError(f"real finger names must be distinct, got {names}")
    threshold = max(min_force, ZERO_FORCE)
    kept = {f.name: f for f in fingers if np.linalg.norm(f.force) > threshold}
    ignored = tuple(sorted(set(names) - set(kept)))
    if not kept:
        raise NoContactsError(
            f"no real finger has a net force above {threshold:.3g} N "
            f"(real fingers with contacts: {sorted(names) or 'none'})"
        )
    partition = best_partition({name: f.force for name, f in kept.items()})
    vfs = tuple(virtual_finger([kept[name] for name in block]) for block in partition.blocks)
    return VirtualFingerGrasp(vfs, partition, ignored)


def virtual_fingers_from_contacts(
    contacts: Iterable[Contact], T_world_object: ArrayLike | None = None, *, min_force: float = 0.0
) -> VirtualFingerGrasp:
    """The best virtual-finger representation of a grasp, in the object frame.

    contacts: contacts of one hand on the object, in the world or the object frame.
    T_world_object: 4x4 pose of the object frame in the world [m]; needed for world-frame
    contacts.
    min_force: [N] see `virtual_fingers_from_real_fingers`.
    Raises NoContactsError when there are no contacts.
    """
    fingers = group_by_real_finger(contacts, T_world_object)
    if not fingers:
        raise NoContactsError("no contacts: a grasp without contacts has no virtual fingers")
    return virtual_fingers_from_real_fingers(fingers, min_force=min_force)


# ----------------------------------------------------------------------------- comparison


@dataclass(frozen=True)
class MatchedPair:
    """One robot virtual finger matched to one human virtual finger.

    robot_index, human_index: positions in the compared sequences.
    position_err_mm: distance between their positions [mm].
    orientation_err_deg: angle between their normals [deg], 0..180.
    """

    robot_index: int
    human_index: int
    position_err_mm: float
    orientation_err_deg: float


@dataclass(frozen=True)
class VirtualFingerComparison:
    """A robot grasp's virtual fingers against the human's, both in the object frame.

    position_err_mm: mean position error over matched pairs [mm].
    orientation_err_deg: mean normal angle over matched pairs [deg].
    robot_count, human_count: numbers of virtual fingers on each side.
    pairs: the one-to-one matching (min(robot_count, human_count) pairs, by robot index).
    unmatched_robot, unmatched_human: indices left without a partner.
    robot_untouched, human_untouched: real fingers of the hand that did not touch (in the
        hand's order), or None when the hand's real-finger names were not given.
    When the counts differ the errors are a lower bound (`is_lower_bound`, `note`).
    """

    position_err_mm: float
    orientation_err_deg: float
    robot_count: int
    human_count: int
    pairs: tuple[MatchedPair, ...]
    unmatched_robot: tuple[int, ...]
    unmatched_human: tuple[int, ...]
    robot_untouched: tuple[str, ...] | None = None
    human_untouched: tuple[str, ...] | None = None

    @property
    def is_lower_bound(self) -> bool:
        """True when the counts differ: unmatched virtual fingers add no error."""
        return self.robot_count != self.human_count

    @property
    def note(self) -> str:
        if not self.is_lower_bound:
            return ""
        return (
            f"robot has {self.robot_count} virtual fingers, human {self.human_count}: the "
            f"errors are means over {len(self.pairs)} matched pairs, a lower bound"
        )

    def to_dict(self) -> dict:
        return {
            "position_err_mm": self.position_err_mm,
            "orientation_err_deg": self.orientation_err_deg,
            "robot_count": self.robot_count,
            "human_count": self.human_count,
            "is_lower_bound": self.is_lower_bound,
            "note": self.note,
            "pairs": [vars(pair) for pair in self.pairs],
            "unmatched_robot": list(self.unmatched_robot),
            "unmatched_human": list(self.unmatched_human),
            "robot_untouched": _list_or_none(self.robot_untouched),
            "human_untouched": _list_or_none(self.human_untouched),
        }


def _list_or_none(names: tuple[str, ...] | None) -> list[str] | None:
    return None if names is None else list(names)


def compare(
    robot: Sequence[VirtualFinger] | VirtualFingerGrasp,
    human: Sequence[VirtualFinger] | VirtualFingerGrasp,
    *,
    robot_real_fingers: Iterable[str] | None = None,
    human_real_fingers: Iterable[str] | None = None,
    weight_per_mm: float = 1.0,
    weight_per_deg: float = 1.0,
) -> VirtualFingerComparison:
    """Match robot virtual fingers to human ones one-to-one and report the errors.

    robot, human: virtual fingers in the same frame (the object frame).
    robot_real_fingers, human_real_fingers: every real finger of each hand (e.g.
        `HandDescription.finger_names`); those in no virtual finger are reported as not
        touching. A virtual-finger member missing from the list raises GraspframeError.
    weight_per_mm, weight_per_deg: matching cost of a pair =
        weight_per_mm * position_err_mm + weight_per_deg * orientation_err_deg
        (defaults: 1 mm of distance costs as much as 1 deg of angle).
    The matching minimises the summed cost (scipy's linear_sum_assignment) over
    min(robot_count, human_count) pairs. Raises NoContactsError when a side is empty:
    there is nothing to compare (never a NaN error).
    """
    robot_vfs = _virtual_finger_tuple(robot, "robot")
    human_vfs = _virtual_finger_tuple(human, "human")
    for weight, what in ((weight_per_mm, "weight_per_mm"), (weight_per_deg, "weight_per_deg")):
        if not (math.isfinite(weight) and weight >= 0.0):
            raise GraspframeError(f"{what} must be a finite weight >= 0, got {weight}")
    if weight_per_mm == 0.0 and weight_per_deg == 0.0:
        raise GraspframeError("weight_per_mm and weight_per_deg cannot both be 0")

    position_err_mm, orientation_err_deg = _pair_errors(robot_vfs, human_vfs)
    cost = weight_per_mm * position_err_mm + weight_per_deg * orientation_err_deg
    rows, cols = linear_sum_assignment(cost)
    pairs = tuple(
        MatchedPair(int(r), int(c), float(position_err_mm[r, c]), float(orientation_err_deg[r, c]))
        for r, c in zip(rows, cols, strict=True)
    )
    return VirtualFingerComparison(
        position_err_mm=float(np.mean([p.position_err_mm for p in pairs])),
        orientation_err_deg=float(np.mean([p.orientation_err_deg for p in pairs])),
        robot_count=len(robot_vfs),
        human_count=len(human_vfs),
        pairs=pairs,
        unmatched_robot=tuple(sorted(set(range(len(robot_vfs))) - set(rows.tolist()))),
        unmatched_human=tuple(sorted(set(range(len(human_vfs))) - set(cols.tolist()))),
        robot_untouched=_untouched(robot_vfs, robot_real_fingers, "robot"),
        human_untouched=_untouched(human_vfs, human_real_fingers, "human"),
    )


def _virtual_finger_tuple(
    vfs: Sequence[VirtualFinger] | VirtualFingerGrasp, side: str
) -> tuple[VirtualFinger, ...]:
    if isinstance(vfs, VirtualFingerGrasp):
        vfs = vfs.virtual_fingers
    vfs = tuple(vfs)
    if not vfs:
        raise NoContactsError(f"{side} side has no virtual fingers (no contacts) to compare")
    if not all(isinstance(vf, VirtualFinger) for vf in vfs):
        raise GraspframeError(f"{side} side must be VirtualFinger values or a VirtualFingerGrasp")
    return vfs


def _pair_errors(
    robot_vfs: Sequence[VirtualFinger], human_vfs: Sequence[VirtualFinger]
) -> tuple[Vectors, Vectors]:
    """(R,H) position errors [mm] and normal angles [deg] of every robot/human pair."""
    p_robot = np.array([vf.position for vf in robot_vfs])
    p_human = np.array([vf.position for vf in human_vfs])
    n_robot = np.array([vf.normal for vf in robot_vfs])
    n_human = np.array([vf.normal for vf in human_vfs])
    position_err_mm = 1000.0 * np.linalg.norm(p_robot[:, None, :] - p_human[None, :, :], axis=2)
    orientation_err_deg = np.degrees(np.arccos(np.clip(n_robot @ n_human.T, -1.0, 1.0)))
    return position_err_mm, orientation_err_deg


def _untouched(
    vfs: Sequence[VirtualFinger], real_fingers: Iterable[str] | None, side: str
) -> tuple[str, ...] | None:
    if real_fingers is None:
        return None
    if isinstance(real_fingers, str):
        raise GraspframeError(f"{side}_real_fingers must be a list of names, not one string")
    hand_fingers = tuple(real_fingers)
    touching = {name for vf in vfs for name in vf.members}
    unknown = sorted(touching - set(hand_fingers))
    if unknown:
        raise GraspframeError(
            f"{side} virtual fingers use real fingers {unknown} that are not in "
            f"{side}_real_fingers {list(hand_fingers)}"
        )
    return tuple(name for name in hand_fingers if name not in touching)
