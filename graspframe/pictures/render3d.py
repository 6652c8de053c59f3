"""Meshes placed in the world -> shaded views, on graspframe/pictures/rasteriser.py's CPU
rasteriser (one OpenGL context per process, `renderer()`).

A `Soup` is a mesh as the rasteriser takes it: three corners per triangle with their
normals (smooth within a crease angle, so boxes keep their edges and cylinders look round)
and albedo. A `Placed` soup has a pose in the world and is either solid or translucent.
A `View` is a pinhole camera (OpenCV frame: x right, y down, z forward) with a pose in
the world; `look_at` and `fit_view` aim it.

Translucency in two passes: the solid soups alone, then the solid and translucent soups
together (only over the translucent soups' bounding box); the two images are mixed at
the translucent opacity. Where a translucent soup is the nearest surface, the picture
shows it over what lies behind it (one layer deep); elsewhere both passes are the same
image.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.transforms import inv_T
from graspframe.pictures.meshes import vertex_normals
from graspframe.pictures.rasteriser import NEAR, Camera, Lighting, Renderer, composite

CREASE_DEG = 35.0  # corners of faces meeting at more than this keep their own normal
MIN_VIEW_DISTANCE = 0.12  # [m] closest a fitted camera comes to its target
VISIBILITY_TOLERANCE = 0.006  # [m] a point this far behind the nearest surface still shows
DEPTH_SUBSAMPLE = 4  # the visibility render is this many times smaller than the view
LIGHTING = Lighting(light_dir=(0.35, -0.55, -0.75), ambient=0.5, specular=0.12)

_RENDERER: Renderer | None = None


def renderer() -> Renderer:
    """The process's rasteriser, created on first use."""
    global _RENDERER
    if _RENDERER is None:
        _RENDERER = Renderer()
    return _RENDERER


@dataclass(frozen=True)
class Soup:
    """Triangles in the soup's frame: positions and normals of each corner (3m, 3) [m],
    albedo RGB in [0, 1] of each corner (3m, 3)."""

    positions: NDArray[np.float32]
    normals: NDArray[np.float32]
    albedo: NDArray[np.float32]

    @classmethod
    def of_mesh(cls, vertices, faces, rgb) -> Soup:
        """A soup of a triangle mesh; `rgb`: one colour (3,) or one per vertex (n, 3)."""
        vertices = np.asarray(vertices, dtype=float)
        faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
        corners = vertices[faces]  # (m, 3, 3)
        face_normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        face_normals /= np.maximum(np.linalg.norm(face_normals, axis=1, keepdims=True), 1e-12)
        normals = vertex_normals(vertices, faces)[faces]
        smooth = np.einsum("fkd,fd->fk", normals, face_normals) >= np.cos(np.radians(CREASE_DEG))
        normals = np.where(smooth[..., None], normals, face_normals[:, None, :])
        rgb = np.asarray(rgb, dtype=np.float32)
        albedo = rgb[faces] if rgb.ndim == 2 else np.broadcast_to(rgb, corners.shape)
        return cls(
            corners.reshape(-1, 3).astype(np.float32),
            normals.reshape(-1, 3).astype(np.float32),
            np.ascontiguousarray(albedo, dtype=np.float32).reshape(-1, 3),
        )

    def __len__(self) -> int:
        return len(self.positions) // 3


@dataclass(frozen=True)
class Placed:
    """A soup at its pose in the world; translucent ones are drawn see-through."""

    soup: Soup
    T_world_soup: NDArray[np.float64]
    translucent: bool = False


@dataclass(frozen=True)
class View:
    """A camera: intrinsics and the camera's pose in the world (OpenCV axes)."""

    camera: Camera
    T_world_camera: NDArray[np.float64]

    def project(self, p_world) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(pixels (n, 2) as (column, row), depth along the view (n,) [m]) of points."""
        p = np.asarray(p_world, dtype=float).reshape(-1, 3)
        T_camera_world = inv_T(self.T_world_camera)
        p_camera = p @ T_camera_world[:3, :3].T + T_camera_world[:3, 3]
        z = p_camera[:, 2]
        safe = np.where(np.abs(z) < 1e-9, 1e-9, z)
        c = self.camera
        pixels = np.stack(
            [c.fx * p_camera[:, 0] / safe + c.cx, c.fy * p_camera[:, 1] / safe + c.cy]
        )
        return pixels.T, z


def look_at(eye, target, up) -> NDArray[np.float64]:
    """T_world_camera of a camera at `eye` looking at `target`, `up` (world) up in the
    picture as far as it can be; up parallel to the view picks another."""
    eye, target = np.asarray(eye, dtype=float), np.asarray(target, dtype=float)
    z = target - eye
    z /= np.linalg.norm(z)
    up = np.asarray(up, dtype=float)
    x = np.cross(z, up)
    if np.linalg.norm(x) < 1e-6:
        x = np.cross(z, np.roll(up, 1))
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    T = np.eye(4)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, y, z, eye
    return T


def fit_view(camera: Camera, points, direction, up, margin: float = 0.08) -> View:
    """The view from `direction` (unit, from the points towards the camera) with `up` up,
    as near as keeps every point inside the picture with `margin` (share of the half
    width) to spare, centred on the points' extent."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    direction = np.asarray(direction, dtype=float)
    direction = direction / np.linalg.norm(direction)
    centre = (points.min(axis=0) + points.max(axis=0)) / 2
    R = look_at(centre + direction, centre, up)[:3, :3]
    local = (points - centre) @ R  # camera axes, origin at the centre
    middle = (local.min(axis=0) + local.max(axis=0)) / 2
    centre = centre + R[:, 0] * middle[0] + R[:, 1] * middle[1]
    local = (points - centre) @ R
    tan_x = (1 - margin) * camera.cx / camera.fx
    tan_y = (1 - margin) * camera.cy / camera.fy
    needed = np.maximum(np.abs(local[:, 0]) / tan_x, np.abs(local[:, 1]) / tan_y) - local[:, 2]
    distance = max(MIN_VIEW_DISTANCE, float(needed.max()))
    eye = centre - R[:, 2] * distance
    return View(camera, look_at(eye, centre, up))


def box_corners(placed: Placed) -> NDArray[np.float64]:
    """(8, 3) [m] world corners of the soup's bounding box in its own frame."""
    low = placed.soup.positions.min(axis=0)
    high = placed.soup.positions.max(axis=0)
    box = np.array(
        [
            [x, y, z]
            for x in (low[0], high[0])
            for y in (low[1], high[1])
            for z in (low[2], high[2])
        ],
        dtype=float,
    )
    T = placed.T_world_soup
    return box @ T[:3, :3].T + T[:3, 3]


def _in_camera(placed: Sequence[Placed], T_camera_world):
    positions, normals, albedo = [], [], []
    for item in placed:
        T = T_camera_world @ item.T_world_soup
        R, t = T[:3, :3].astype(np.float32), T[:3, 3].astype(np.float32)
        positions.append(item.soup.positions @ R.T + t)
        normals.append(item.soup.normals @ R.T)
        albedo.append(item.soup.albedo)
    if not positions:
        empty = np.zeros((0, 3), dtype=np.float32)
        return empty, empty, empty
    return np.concatenate(positions), np.concatenate(normals), np.concatenate(albedo)


def render(
    placed: Sequence[Placed], view: View, background_bgr, translucent_opacity: float = 0.5
) -> NDArray[np.uint8]:
    """The BGR image (H x W x 3) of the placed soups over a plain background colour."""
    c = view.camera
    background = np.empty((c.height, c.width, 3), dtype=np.uint8)
    background[:] = np.asarray(background_bgr, dtype=np.uint8)
    solid = [p for p in placed if not p.translucent]
    image = _draw(solid, view, background)
    translucent = [p for p in placed if p.translucent]
    region = _region(translucent, view)
    if region is None:
        return image
    # The second pass only where the translucent soups can be: a camera cropped to their
    # bounding box (same intrinsics, shifted by whole pixels: the same samples).
    x0, y0, x1, y1 = region
    crop = View(Camera(x1 - x0, y1 - y0, c.fx, c.fy, c.cx - x0, c.cy - y0), view.T_world_camera)
    both = _draw(solid + translucent, crop, background[y0:y1, x0:x1])
    mixed = (1 - translucent_opacity) * image[y0:y1, x0:x1].astype(np.float32)
    mixed += translucent_opacity * both
    image[y0:y1, x0:x1] = np.clip(mixed + 0.5, 0, 255).astype(np.uint8)
    return image


def _region(placed: Sequence[Placed], view: View) -> tuple[int, int, int, int] | None:
    """(x0, y0, x1, y1) pixel bounds of the soups' bounding boxes in the view (the whole
    picture when one reaches behind the camera), None when there is nothing to draw."""
    if not placed:
        return None
    c = view.camera
    pixels, depth = view.project(np.concatenate([box_corners(item) for item in placed]))
    if np.any(depth <= NEAR):
        return 0, 0, c.width, c.height
    x0, y0 = np.floor(pixels.min(axis=0)).astype(int) - 1
    x1, y1 = np.ceil(pixels.max(axis=0)).astype(int) + 1
    x0, y0 = max(int(x0), 0), max(int(y0), 0)
    x1, y1 = min(int(x1), c.width), min(int(y1), c.height)
    if x1 <= x0 or y1 <= y0:
        return None
    return x0, y0, x1, y1


def visible(
    placed: Sequence[Placed], view: View, p_world, tolerance: float = VISIBILITY_TOLERANCE
) -> NDArray[np.bool_]:
    """Whether each point (n, 3) [m] is in sight: in front of the camera and not more than
    `tolerance` [m] behind the nearest surface of `placed` (all drawn solid) at its pixel.

    The nearest depth comes from a render at 1/DEPTH_SUBSAMPLE of the view's size with
    the depth, scaled to the placed soups' depth range, as unlit albedo (256 levels);
    points off the picture or where the render is not fully covered count as visible.
    """
    pixels, depth = view.project(p_world)
    in_sight = depth > 0
    positions, normals, _ = _in_camera(placed, inv_T(view.T_world_camera))
    if not len(positions) or not np.any(in_sight):
        return in_sight
    z = positions[:, 2]
    near, far = float(max(z.min(), 0.0)), float(z.max())
    span = max(far - near, 1e-6)
    albedo = np.zeros_like(positions)
    albedo[:, 0] = np.clip((z - near) / span, 0.0, 1.0)
    c, k = view.camera, DEPTH_SUBSAMPLE
    small = Camera(c.width // k, c.height // k, c.fx / k, c.fy / k, c.cx / k, c.cy / k)
    unlit = Lighting(ambient=1.0, specular=0.0)
    bgr, coverage = renderer().render(small, positions, normals, albedo, unlit)
    nearest = near + span * bgr[..., 2].astype(float) / 255.0
    columns = np.floor(pixels[:, 0] / k).astype(int)
    rows = np.floor(pixels[:, 1] / k).astype(int)
    inside = (columns >= 0) & (columns < small.width) & (rows >= 0) & (rows < small.height)
    for i in np.flatnonzero(in_sight & inside):
        if coverage[rows[i], columns[i]] > 0.99:
            in_sight[i] = depth[i] <= nearest[rows[i], columns[i]] + tolerance
    return in_sight


def _draw(placed, view: View, background) -> NDArray[np.uint8]:
    positions, normals, albedo = _in_camera(placed, inv_T(view.T_world_camera))
    if not len(positions):
        return background.copy()
    bgr, alpha = renderer().render(view.camera, positions, normals, albedo, LIGHTING)
    return composite(bgr, alpha, background)
