"""The object's position on the table from a depth image: the object's known model fitted
to the measured points (point-to-plane ICP over the model's side facing the camera).

The object stands on the table at its believed orientation, so the fit estimates its
position on the table (x, y); its height is the table's. The points taken are those with
a return, not the robot's (perception/self_filter.py), above the table top by more than
the sensor's noise and within SEARCH_RADIUS of the believed position (more than the
largest position error the fit is meant to correct). The fit starts from the believed
position and from the points' centroid and keeps the better result. It is accepted when
enough points lie on the fitted surface (`ObjectFit.accepted`); a rejected fit says why
and is not to be used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from graspframe.hal.depth_camera import DepthImage
from graspframe.hal.objects import ObjectDescription
from graspframe.robot_models.shapes import object_mesh

SEARCH_RADIUS = 0.12  # [m] horizontal, around the believed position
ABOVE_TABLE = 0.008  # [m] points lower than this above the table top are the table
MODEL_POINTS = 4000  # samples of the model's surface
ICP_ITERATIONS = 30
MATCH_DISTANCES = (0.04, 0.02, 0.01)  # [m] correspondence gates, tightened in turn
INLIER_DISTANCE = 0.006  # [m] a point this close to the fitted surface is on it
MIN_POINTS = 60  # fewer points on the object: no fit
MIN_INLIER_FRACTION = 0.7
MAX_RMS = 0.005  # [m] of the inliers' point-to-plane distance


@dataclass(frozen=True)
class ObjectFit:
    """The fitted object pose in the world, how well it fits, whether to use it.

    p_world_xy: [m] the fitted position on the table; shift_xy: [m] from the believed
    position; points: measured points on or near the object; inlier_fraction: share of
    them within INLIER_DISTANCE of the fitted surface; rms_mm: their point-to-plane
    distance; accepted; reason: why not, when not."""

    T_world_object: NDArray[np.float64]
    shift_xy: tuple[float, float]
    points: int
    inlier_fraction: float
    rms_mm: float
    accepted: bool
    reason: str | None

    def to_json(self) -> dict:
        return {
            "p_world_object": self.T_world_object[:3, 3].tolist(),
            "shift_mm": [1000.0 * v for v in self.shift_xy],
            "points": self.points,
            "inlier_fraction": self.inlier_fraction,
            "rms_mm": self.rms_mm,
            "accepted": self.accepted,
            "reason": self.reason,
        }


class ObjectModel:
    """Samples of an object's surface with their outward normals, in the object frame."""

    def __init__(self, obj: ObjectDescription, seed: int = 0) -> None:
        mesh = object_mesh(obj)
        rng = np.random.default_rng(seed)
        areas = mesh.area_faces
        faces = rng.choice(len(areas), size=MODEL_POINTS, p=areas / areas.sum())
        corners = mesh.vertices[mesh.faces[faces]]  # (n, 3, 3)
        u, v = rng.random((2, MODEL_POINTS, 1))
        flip = (u + v) > 1.0
        u, v = np.where(flip, 1.0 - u, u), np.where(flip, 1.0 - v, v)
        self.p_object = (
            corners[:, 0]
            + u * (corners[:, 1] - corners[:, 0])
            + v * (corners[:, 2] - corners[:, 0])
        )
        self.n_object = np.asarray(mesh.face_normals[faces], dtype=float)


def object_points(
    image: DepthImage, p_world_believed: NDArray[np.float64], table_height: float
) -> NDArray[np.float64]:
    """(n, 3) [m] measured points that may be the object's (see the module's docstring)."""
    p = image.points_world()
    near = np.linalg.norm(p[:, :2] - p_world_believed[:2], axis=1) <= SEARCH_RADIUS
    return p[near & (p[:, 2] > table_height + ABOVE_TABLE)]


def fit_object(
    image: DepthImage,
    model: ObjectModel,
    T_world_object_believed: NDArray[np.float64],
    table_height: float,
) -> ObjectFit:
    """The object's position fitted to `image` (the robot already removed from it)."""
    believed = T_world_object_believed[:3, 3]
    points = object_points(image, believed, table_height)
    if len(points) < MIN_POINTS:
        return _rejected(
            T_world_object_believed,
            len(points),
            f"{len(points)} points on the object, fewer than {MIN_POINTS}",
        )
    eye = image.T_world_camera[:3, 3]
    R = T_world_object_believed[:3, :3]
    starts = [believed[:2], points[:, :2].mean(axis=0)]
    best: tuple[float, float, NDArray[np.float64]] | None = None
    for start in starts:
        xy = _icp(points, model, R, np.array([*start, believed[2]]), eye)
        inliers, rms = _quality(points, model, R, np.array([*xy, believed[2]]), eye)
        if best is None or (inliers, -rms) > (best[0], -best[1]):
            best = (inliers, rms, xy)
    assert best is not None
    inlier_fraction, rms, xy = best
    T_fit = T_world_object_believed.copy()
    T_fit[:2, 3] = xy
    shift = (float(xy[0] - believed[0]), float(xy[1] - believed[1]))
    reason = None
    if inlier_fraction < MIN_INLIER_FRACTION:
        reason = (
            f"{100 * inlier_fraction:.0f} % of the points on the fitted surface, "
            f"fewer than {100 * MIN_INLIER_FRACTION:.0f} %"
        )
    elif rms > MAX_RMS:
        reason = f"residual {1000 * rms:.1f} mm, more than {1000 * MAX_RMS:.1f} mm"
    return ObjectFit(T_fit, shift, len(points), inlier_fraction, 1000 * rms, reason is None, reason)


def _rejected(T_world_object: NDArray[np.float64], points: int, reason: str) -> ObjectFit:
    return ObjectFit(T_world_object.copy(), (0.0, 0.0), points, 0.0, float("nan"), False, reason)


def _facing(
    model: ObjectModel,
    R: NDArray[np.float64],
    p_world_object: NDArray[np.float64],
    eye: NDArray[np.float64],
) -> tuple[NDArray, NDArray]:
    """The model's samples facing the camera at `eye`, in the world: (points, normals)."""
    p = model.p_object @ R.T + p_world_object
    n = model.n_object @ R.T
    toward = np.einsum("ij,ij->i", n, eye - p) > 0.0
    return p[toward], n[toward]


def _icp(
    points: NDArray[np.float64],
    model: ObjectModel,
    R: NDArray[np.float64],
    p_start: NDArray[np.float64],
    eye: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Point-to-plane ICP over the horizontal translation; returns the fitted (x, y)."""
    p_object = p_start.astype(float).copy()
    per_gate = ICP_ITERATIONS // len(MATCH_DISTANCES)
    for gate in MATCH_DISTANCES:
        for _ in range(per_gate):
            surface, normals = _facing(model, R, p_object, eye)
            distance, index = cKDTree(surface).query(points, distance_upper_bound=gate)
            matched = np.isfinite(distance)
            if matched.sum() < 3:
                break
            q, n = surface[index[matched]], normals[index[matched]]
            residual = np.einsum("ij,ij->i", points[matched] - q, n)
            A = n[:, :2]
            # Point-to-plane on (dx, dy), damped toward point-to-point along the surface.
            step = np.linalg.lstsq(
                np.vstack([A, 0.1 * np.eye(2)]), np.concatenate([residual, [0.0, 0.0]]), rcond=None
            )[0]
            p_object[:2] += step
            if np.linalg.norm(step) < 1e-5:
                break
    return p_object[:2].copy()


def _quality(
    points: NDArray[np.float64],
    model: ObjectModel,
    R: NDArray[np.float64],
    p_object: NDArray[np.float64],
    eye: NDArray[np.float64],
) -> tuple[float, float]:
    """(share of points within INLIER_DISTANCE of the surface, their rms distance [m])."""
    surface, normals = _facing(model, R, p_object, eye)
    distance, index = cKDTree(surface).query(points)
    plane = np.abs(np.einsum("ij,ij->i", points - surface[index], normals[index]))
    close = (distance < 2 * INLIER_DISTANCE) & (plane < INLIER_DISTANCE)
    if not close.any():
        return 0.0, float("inf")
    return float(close.mean()), float(np.sqrt(np.mean(plane[close] ** 2)))
