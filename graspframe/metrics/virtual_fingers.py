"""Virtual fingers: the method's grasp-similarity metric (docs/method.md, 5), on arrays.

A real finger is one finger or the palm; a virtual finger is a set of real fingers whose
forces act in unison. The steps, each a pure function:

1. `group_by_real_finger`: contacts (from any source) -> one `RealFingerContacts` per
   real finger, in a common frame (the object frame in practice).
2. `force_coupling` / `pair_cohesion`: D_c = cos(f_i, f_j) and m_ij = (1 + D_c) / 2 of two
   real fingers' net forces (the sum of their contact forces).
3. `cohesive_index`: C_Vk, the geometric mean of m_ij over the pairs inside a virtual
   finger (1 for a single real finger).
4. `effective_cohesion`: C_eff = ((1 / N!) * prod_k C_Vk) ** (1 / N) of a partition, and
   `best_partition`: the partition of the touching real fingers that maximises it.
5. `virtual_finger`: the pose of a virtual finger (mean contact position and normalised
   mean contact normal over its T(V_k) contacts).
6. `compare`: robot virtual fingers against the human's, matched one-to-one.

What the formula gives, written out because the method's prose says otherwise: with
m_ij = (1 + cos) / 2, parallel forces give m = 1, PERPENDICULAR forces give m = 0.5 and
OPPOSED forces give m = 0. The method's sentence "any perpendicular pair gives 0" holds for
an opposed pair, not a perpendicular one; this module implements the formula.

Positions are in metres, forces in newtons, normals are unit vectors; errors reported in
millimetres and degrees carry the suffixes `_mm` and `_deg`. No simulator is imported.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from more_itertools import set_partitions
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment

from graspframe.contacts import WORLD, Contact
from graspframe.errors import GraspframeError
from graspframe.transforms import as_pose

UNIT_NORMAL_TOL = 1e-4
"""A normal is accepted as unit when | |n| - 1 | <= this."""
ZERO_FORCE = 1e-12
"""[N] A net force at or below this magnitude has no direction (D_c is undefined)."""
MIN_MEAN_NORMAL = 1e-6
"""Length of the mean of unit normals below which a virtual finger has no orientation."""
TIE_TOL = 1e-12
"""Two C_eff values closer than this are a tie (broken as `best_partition` documents)."""

Vectors = NDArray[np.float64]


class NoContactsError(GraspframeError):
    """There are no (force-bearing) contacts, so there are no virtual fingers to build."""


# ----------------------------------------------------------------------------- validation


def _vectors(
    values: ArrayLike | Sequence[ArrayLike], what: str, count: int | None = None
) -> Vectors:
    """A read-only float copy of `values` as (N,3), N >= 1, finite; N == count if given."""
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise GraspframeError(f"{what} must be numbers in an (N,3) array") from None
    if array.ndim != 2 or array.shape[1] != 3 or array.shape[0] == 0:
        raise GraspframeError(f"{what} must have shape (N,3) with N >= 1, got {array.shape}")
    if count is not None and array.shape[0] != count:
        raise GraspframeError(f"{what} must have {count} rows (one per contact), got {len(array)}")
    if not np.all(np.isfinite(array)):
        raise GraspframeError(f"{what} contains NaN or infinite values")
    array.setflags(write=False)
    return array


def _unit_vectors(values: ArrayLike, what: str, count: int | None = None) -> Vectors:
    array = _vectors(values, what, count)
    lengths = np.linalg.norm(array, axis=1)
    worst = int(np.argmax(np.abs(lengths - 1.0)))
    if abs(lengths[worst] - 1.0) > UNIT_NORMAL_TOL:
        raise GraspframeError(
            f"{what} must be unit vectors (|n| = 1 +- {UNIT_NORMAL_TOL}); "
            f"row {worst} has length {lengths[worst]:.6g}"
        )
    return array


def _force_directions(forces: ArrayLike | Sequence[ArrayLike], what: str = "forces") -> Vectors:
    """Unit directions of (F,3) forces [N]; a zero force has none and is rejected."""
    forces = _vectors(forces, what)
    magnitudes = np.linalg.norm(forces, axis=1)
    weakest = int(np.argmin(magnitudes))
    if magnitudes[weakest] <= ZERO_FORCE:
        raise GraspframeError(
            f"{what} row {weakest} is a zero force ({magnitudes[weakest]:.3g} N); "
            f"the force coupling needs forces above {ZERO_FORCE} N"
        )
    return forces / magnitudes[:, None]


def _force(f: ArrayLike, what: str) -> Vectors:
    try:
        row = np.asarray(f, dtype=float).reshape(1, 3)
    except (TypeError, ValueError):
        raise GraspframeError(f"{what} must be a 3-vector force [N]") from None
    return _force_directions(row, what)[0]


# ----------------------------------------------------------------------------- real fingers


@dataclass(frozen=True, eq=False)
class RealFingerContacts:
    """The contacts of one real finger, all in one common frame (the object frame).

    name: real finger name (a finger or the palm).
    positions: (N,3) contact positions [m].
    normals: (N,3) unit contact normals, from the object into the hand.
    forces: (N,3) forces the finger exerts on the object at each contact [N].
    Arrays are copied and made read-only; N >= 1.
    """

    name: str
    positions: Vectors
    normals: Vectors
    forces: Vectors

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise GraspframeError(f"real finger name must be a non-empty string, got {self.name!r}")
        what = f"real finger {self.name!r}"
        positions = _vectors(self.positions, f"{what} positions")
        count = len(positions)
        object.__setattr__(self, "positions", positions)
        object.__setattr__(self, "normals", _unit_vectors(self.normals, f"{what} normals", count))
        object.__setattr__(self, "forces", _vectors(self.forces, f"{what} forces", count))

    @property
    def contact_count(self) -> int:
        return len(self.positions)

    @property
    def force(self) -> Vectors:
        """(3,) net force of the real finger: the sum of its contact forces [N]."""
        return self.forces.sum(axis=0)


def group_by_real_finger(
    contacts: Iterable[Contact], T_world_object: ArrayLike | None = None
) -> tuple[RealFingerContacts, ...]:
    """Contacts grouped by `Contact.real_finger`, in the object frame (sorted by name).

    contacts: contacts in the world or the object frame (`Contact.frame`).
    T_world_object: 4x4 pose of the object frame in the world [m]; needed when a contact
    is in the world frame.
    Returns an empty tuple when there are no contacts.
    """
    T = None if T_world_object is None else as_pose(T_world_object, "T_world_object")
    rows: dict[str, list[Contact]] = {}
    for contact in contacts:
        if not isinstance(contact, Contact):
            raise GraspframeError(f"expected graspframe.contacts.Contact, got {type(contact)}")
        if contact.frame == WORLD:
            if T is None:
                raise GraspframeError("world-frame contacts need T_world_object")
            contact = contact.in_object_frame(T)
        rows.setdefault(contact.real_finger, []).append(contact)
    return tuple(
        RealFingerContacts(
            name=name,
            positions=np.array([c.p for c in group]),
            normals=np.array([c.n for c in group]),
            forces=np.array([c.f for c in group]),
        )
        for name, group in sorted(rows.items())
    )


# ----------------------------------------------------------------------------- cohesion


def force_coupling(f_i: ArrayLike, f_j: ArrayLike) -> float:
    """D_c(i, j) = f_i . f_j / (|f_i| |f_j|) in [-1, 1] for two net forces (3,) [N].

    1: parallel, 0: perpendicular, -1: opposed. Zero forces raise GraspframeError.
    """
    cos = float(_force(f_i, "f_i") @ _force(f_j, "f_j"))
    return min(1.0, max(-1.0, cos))


def pair_cohesion(f_i: ArrayLike, f_j: ArrayLike) -> float:
    """m_ij = (1 + D_c(i, j)) / 2 in [0, 1]: parallel 1, perpendicular 0.5, opposed 0."""
    return (1.0 + force_coupling(f_i, f_j)) / 2.0


def _pair_cohesion_matrix(directions: Vectors) -> Vectors:
    """(F,F) m_ij for unit force directions (F,3)."""
    cos = np.clip(directions @ directions.T, -1.0, 1.0)
    return (1.0 + cos) / 2.0


def _geometric_mean_of_pairs(m: Vectors, members: Sequence[int]) -> float:
    """C of the real fingers `members` (indices into the m_ij matrix)."""
    if len(members) < 2:
        return 1.0
    idx = np.asarray(members)
    i, j = np.triu_indices(len(idx), k=1)
    pairs = m[idx[i], idx[j]]
    if np.any(pairs <= 0.0):
        return 0.0  # an exactly opposed pair: the product, hence the mean, is 0
    return float(np.exp(np.mean(np.log(pairs))))


def cohesive_index(forces: ArrayLike) -> float:
    """C_Vk in [0, 1]: geometric mean of m_ij over all pairs of the real fingers in one
    virtual finger, C_Vk = prod_{i<j} m_ij ** (1 / C(F, 2)).

    forces: (F,3) net force of each real finger in the virtual finger [N], F >= 1.
    One real finger gives 1; all parallel forces give 1; one perpendicular pair alone gives
    0.5 (not 0 as the method's prose says; docs/method.md, section 5); any opposed pair gives 0.
    """
    directions = _force_directions(forces)
    return _geometric_mean_of_pairs(_pair_cohesion_matrix(directions), range(len(directions)))


def effective_cohesion(cohesive_indices: Sequence[float]) -> float:
    """C_eff = ((1 / N!) * prod_k C_Vk) ** (1 / N) of a partition into N virtual fingers.

    cohesive_indices: C_Vk of each virtual finger, each in [0, 1], N >= 1.
    """
    values = [float(c) for c in cohesive_indices]
    if not values:
        raise GraspframeError("effective_cohesion needs at least one cohesive index")
    if not all(0.0 <= c <= 1.0 for c in values):
        raise GraspframeError(f"cohesive indices must lie in [0, 1], got {values}")
    n = len(values)
    return (math.prod(values) / math.factorial(n)) ** (1.0 / n)


@dataclass(frozen=True)
class Partition:
    """Real fingers split into virtual fingers, with the cohesion of the split.

    blocks: one tuple of real-finger names per virtual finger; names sorted inside a
        block, blocks sorted lexicographically.
    cohesive_indices: C_Vk of each block [0..1], in block order.
    c_eff: effective cohesion of the partition [0..1].
    """

    blocks: tuple[tuple[str, ...], ...]
    cohesive_indices: tuple[float, ...]
    c_eff: float

    @property
    def count(self) -> int:
        """N, the number of virtual fingers."""
        return len(self.blocks)


def best_partition(forces: Mapping[str, ArrayLike]) -> Partition:
    """The partition of the real fingers into virtual fingers with the largest C_eff.

    forces: real finger name -> its net force (3,) [N]; every force must be nonzero.
    Searches every set partition into N = 1..F blocks (Bell(F) of them: 203 for F = 6,
    115975 for F = 10), computing each block's C_Vk once.
    Ties (C_eff within TIE_TOL) go to the fewest virtual fingers, then to the partition
    whose sorted list of sorted blocks of names is lexicographically smallest, so the
    result does not depend on the order of `forces`.
    Raises NoContactsError when `forces` is empty.
    """
    if not forces:
        raise NoContactsError("no real fingers to partition: forces is empty")
    names = sorted(forces)
    if not all(isinstance(name, str) for name in names):
        raise GraspframeError(f"real finger names must be strings, got {names}")
    directions = _force_directions([forces[name] for name in names], "real finger forces")
    m = _pair_cohesion_matrix(directions)
    block_cohesion: dict[tuple[int, ...], float] = {}

    def cohesion(block: list[int]) -> float:
        key = tuple(block)
        if key not in block_cohesion:
            block_cohesion[key] = _geometric_mean_of_pairs(m, sorted(block))
        return block_cohesion[key]

    best: tuple[float, tuple[tuple[int, ...], ...]] | None = None
    for n in range(1, len(names) + 1):
        scale = 1.0 / math.factorial(n)
        for blocks in set_partitions(range(len(names)), n):
            c_eff = (math.prod(cohesion(b) for b in blocks) * scale) ** (1.0 / n)
            if best is None or c_eff > best[0] + TIE_TOL:
                best = (c_eff, _canonical(blocks))
            elif c_eff >= best[0] - TIE_TOL and len(best[1]) == n:
                canonical = _canonical(blocks)
                if canonical < best[1]:
                    best = (c_eff, canonical)
    assert best is not None
    c_eff, canonical = best
    return Partition(
        blocks=tuple(tuple(names[i] for i in block) for block in canonical),
        cohesive_indices=tuple(cohesion(list(block)) for block in canonical),
        c_eff=float(c_eff),
    )


def _canonical(blocks: Iterable[Iterable[int]]) -> tuple[tuple[int, ...], ...]:
    """Blocks of (name-sorted) indices, each sorted, in sorted order."""
    return tuple(sorted(tuple(sorted(block)) for block in blocks))


# ----------------------------------------------------------------------------- virtual fingers


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
        position = _vectors(np.reshape(self.position, (1, -1)), f"position of {members}")[0]
        normal = _unit_vectors(np.reshape(self.normal, (1, -1)), f"normal of {members}")[0]
        if int(self.contact_count) < 1:
            raise GraspframeError(f"contact_count must be >= 1, got {self.contact_count}")
        if not 0.0 <= float(self.cohesive_index) <= 1.0:
            raise GraspframeError(f"cohesive_index must lie in [0, 1], got {self.cohesive_index}")
        object.__setattr__(self, "members", members)
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "normal", normal)

    def to_dict(self) -> dict:
        return {
            "members": list(self.members),
            "position": [float(v) for v in self.position],
            "normal": [float(v) for v in self.normal],
            "contact_count": self.contact_count,
            "cohesive_index": self.cohesive_index,
        }


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
            "virtual_fingers": [vf.to_dict() for vf in self.virtual_fingers],
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
