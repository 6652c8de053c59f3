"""Grasp quality from contacts: the grasp wrench space, the Ferrari-Canny epsilon and the
wrench-space volume.

Ferrari & Canny, "Planning optimal grasps", IEEE ICRA 1992; the linearised friction cone
and the L1 / L-infinity wrench spaces as in Miller & Allen, "GraspIt! A versatile
simulator for robotic grasping", IEEE RAM 2004, and Murray, Li & Sastry, "A Mathematical
Introduction to Robotic Manipulation", CRC 1994, ch. 5.

Each contact i is a point p_i with the unit normal n_i pointing into the object, and
Coulomb friction mu. Its friction cone is replaced by the pyramid of `edges` unit-normal
forces f_ij = n_i + mu (cos(theta_j) t1_i + sin(theta_j) t2_i), theta_j = 2 pi j / edges,
each with the wrench w_ij = (f_ij, (p_i - c) x f_ij / torque_length): torques about the
reference point c (the object's centroid) are divided by a length so that forces and
torques share a unit.

- L1 wrench space: the convex hull of every w_ij (the contact normal forces sum to at
  most 1).
- L-infinity wrench space: the Minkowski sum over contacts of the hull of {0, w_i1, ...}
  (each contact's normal force is at most 1).
- epsilon: the radius of the largest ball around the origin inside the wrench space (0
  when the origin is not strictly inside: no force closure). volume: its volume.

`space="force"` measures the same in the 3-D force space alone (torques left out), the
reference for grasps whose contacts cannot resist every torque by construction (two
point contacts never resist a torque about the line through them).

Cost (`python benchmarks/quality.py`): the L1 quality of a 4-contact grasp takes about
1.5 ms; the L-infinity one needs the Minkowski sum of the contacts' wrench sets, whose
6-D hull takes seconds (0.6 s with 4 pyramid edges, 10 s with 8), so it is computed only
when asked for (`linf=True`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import ConvexHull

from graspframe.common.errors import GraspframeError

DEFAULT_EDGES = 8  # sides of the pyramid that stands in for each friction cone
SPACES = ("wrench", "force")


@dataclass(frozen=True)
class GraspQuality:
    """epsilon_l1, epsilon_linf: Ferrari-Canny epsilon [-] (forces in units of the summed
    (L1) or the largest (L-infinity) contact normal force, torques over torque_length);
    volume_l1, volume_linf: volumes of the two wrench spaces (the L-infinity values are
    None when not asked for); plus how they were computed."""

    epsilon_l1: float
    epsilon_linf: float | None
    volume_l1: float
    volume_linf: float | None
    friction: float
    edges: int
    torque_length: float
    space: str
    n_contacts: int

    @property
    def force_closure(self) -> bool:
        return self.epsilon_l1 > 0.0

    def to_dict(self) -> dict:
        return {
            "epsilon_l1": self.epsilon_l1,
            "epsilon_linf": self.epsilon_linf,
            "volume_l1": self.volume_l1,
            "volume_linf": self.volume_linf,
            "force_closure": self.force_closure,
            "friction": self.friction,
            "edges": self.edges,
            "torque_length": self.torque_length,
            "space": self.space,
            "n_contacts": self.n_contacts,
        }


def tangent_basis(n: NDArray[np.float64], lever: NDArray[np.float64]) -> tuple:
    """Two unit tangents (t1, t2) at a contact with unit normal n. t1 follows the contact's
    lever arm (n x lever) when that is defined, so that the basis moves with the grasp
    under a rigid motion; otherwise it is taken across the normal's smallest component."""
    t1 = np.cross(n, lever)
    if np.linalg.norm(t1) < 1e-9 * max(1.0, float(np.linalg.norm(lever))):
        axis = np.zeros(3)
        axis[int(np.argmin(np.abs(n)))] = 1.0
        t1 = np.cross(n, axis)
    t1 = t1 / np.linalg.norm(t1)
    return t1, np.cross(n, t1)


def contact_wrenches(
    points: ArrayLike,
    normals: ArrayLike,
    friction: float,
    centre: ArrayLike = (0.0, 0.0, 0.0),
    torque_length: float = 1.0,
    edges: int = DEFAULT_EDGES,
    space: str = "wrench",
) -> NDArray[np.float64]:
    """(contacts, edges, 6) primitive wrenches (or (contacts, edges, 3) forces)."""
    p, n = _contacts(points, normals)
    if not (friction >= 0 and math.isfinite(friction)):
        raise GraspframeError(f"friction must be a finite number >= 0, got {friction}")
    if not torque_length > 0:
        raise GraspframeError(f"torque_length must be > 0 [m], got {torque_length}")
    if edges < 3:
        raise GraspframeError(f"a friction pyramid needs at least 3 edges, got {edges}")
    if space not in SPACES:
        raise GraspframeError(f"unknown space {space!r}; spaces: {', '.join(SPACES)}")
    c = np.asarray(centre, dtype=float)
    angles = 2.0 * math.pi * np.arange(edges) / edges
    wrenches = []
    for p_i, n_i in zip(p, n, strict=True):
        t1, t2 = tangent_basis(n_i, p_i - c)
        forces = n_i + friction * (np.outer(np.cos(angles), t1) + np.outer(np.sin(angles), t2))
        if space == "force":
            wrenches.append(forces)
        else:
            torques = np.cross(p_i - c, forces) / torque_length
            wrenches.append(np.hstack([forces, torques]))
    return np.asarray(wrenches)


def grasp_quality(
    points: ArrayLike,
    normals: ArrayLike,
    friction: float,
    centre: ArrayLike = (0.0, 0.0, 0.0),
    torque_length: float = 1.0,
    edges: int = DEFAULT_EDGES,
    space: str = "wrench",
    linf: bool = False,
) -> GraspQuality:
    """Ferrari-Canny epsilon (L1, and L-infinity with `linf`) and wrench-space volumes.

    points [m], normals (unit, into the object), friction: the object's Coulomb
    coefficient; centre [m]: the torque reference (the object's centroid); torque_length
    [m]: torques are divided by it (e.g. the object's largest radius); space: "wrench"
    (6-D) or "force" (3-D)."""
    w = contact_wrenches(points, normals, friction, centre, torque_length, edges, space)
    eps_l1, vol_l1 = _hull_quality(w.reshape(-1, w.shape[-1]))
    eps_linf = vol_linf = None
    if linf:
        eps_linf, vol_linf = _hull_quality(_minkowski_sum(w))
    return GraspQuality(
        eps_l1, eps_linf, vol_l1, vol_linf, friction, edges, torque_length, space, len(w)
    )


def _contacts(
    points: ArrayLike, normals: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(N,3) contact points [m] and unit normals, checked."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    n = np.asarray(normals, dtype=float).reshape(-1, 3)
    if len(p) == 0 or len(p) != len(n):
        raise GraspframeError(
            f"grasp quality needs one normal per contact point, got {len(p)} points and "
            f"{len(n)} normals"
        )
    norms = np.linalg.norm(n, axis=1)
    if not np.all(np.isfinite(p)) or not np.all(norms > 1e-12):
        raise GraspframeError("contact points must be finite and normals non-zero")
    return p, n / norms[:, None]


def _minkowski_sum(wrenches: NDArray[np.float64]) -> NDArray[np.float64]:
    """Vertices of the sum over contacts of conv({0} u contact wrenches), pruned to the
    hull's vertices after each contact so the point count stays small."""
    total = np.zeros((1, wrenches.shape[-1]))
    for w_i in wrenches:
        options = np.vstack([np.zeros((1, w_i.shape[-1])), w_i])
        total = (total[:, None, :] + options[None, :, :]).reshape(-1, w_i.shape[-1])
        total = _hull_vertices(total)
    return total


def _is_flat(points: NDArray[np.float64]) -> bool:
    """True when the points span less than their full dimension (no interior)."""
    centred = points - points.mean(axis=0)
    singular = np.linalg.svd(centred, compute_uv=False)
    return len(points) <= points.shape[1] or singular[-1] <= 1e-9 * max(singular[0], 1e-12)


def _hull(points: NDArray[np.float64]) -> ConvexHull:
    # Joggled input ("QJ"): wrench sets are full of exactly coplanar facets (symmetric
    # friction pyramids), on which qhull's exact merging can fail.
    return ConvexHull(points, qhull_options="QJ")


def _hull_vertices(points: NDArray[np.float64]) -> NDArray[np.float64]:
    if _is_flat(points):  # a lower-dimensional set: keep its points
        return np.unique(points.round(12), axis=0)
    return points[_hull(points).vertices]


def _hull_quality(points: NDArray[np.float64]) -> tuple[float, float]:
    """(epsilon, volume) of the convex hull of points; (0, 0) when it is flat (no
    interior: the origin cannot be strictly inside)."""
    if _is_flat(points):
        return 0.0, 0.0
    hull = _hull(points)
    # Facet equations: unit normal . x + offset <= 0 inside; -offset is the facet's
    # distance from the origin (negative when the origin is outside it).
    epsilon = float(np.min(-hull.equations[:, -1]))
    return max(epsilon, 0.0), float(hull.volume)
