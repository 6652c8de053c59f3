"""Cohesion: how well real fingers act in unison, and the best split into virtual fingers.

Steps 2 to 4 of the virtual-finger metric (docs/method.md, 5), on real fingers' net
forces:

2. `force_coupling` / `pair_cohesion`: D_c = cos(f_i, f_j) and m_ij = (1 + D_c) / 2 of two
   real fingers' net forces (the sum of their contact forces).
3. `cohesive_index`: C_Vk, the geometric mean of m_ij over the pairs inside a virtual
   finger (1 for a single real finger).
4. `effective_cohesion`: C_eff = ((1 / N!) * prod_k C_Vk) ** (1 / N) of a partition, and
   `best_partition`: the partition of the touching real fingers that maximises it.

What the formula gives, written out because the method's prose says otherwise: with
m_ij = (1 + cos) / 2, parallel forces give m = 1, PERPENDICULAR forces give m = 0.5 and
OPPOSED forces give m = 0. The method's sentence "any perpendicular pair gives 0" holds for
an opposed pair, not a perpendicular one; this module implements the formula.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from more_itertools import set_partitions
from numpy.typing import ArrayLike

from graspframe.common.errors import GraspframeError, NoContactsError
from graspframe.metrics.vectors import Vectors, force_direction, force_directions

TIE_TOL = 1e-12
"""Two C_eff values closer than this are a tie (broken as `best_partition` documents)."""


def force_coupling(f_i: ArrayLike, f_j: ArrayLike) -> float:
    """D_c(i, j) = f_i . f_j / (|f_i| |f_j|) in [-1, 1] for two net forces (3,) [N].

    1: parallel, 0: perpendicular, -1: opposed. Zero forces raise GraspframeError.
    """
    cos = float(force_direction(f_i, "f_i") @ force_direction(f_j, "f_j"))
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
    directions = force_directions(forces)
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
    directions = force_directions([forces[name] for name in names], "real finger forces")
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
