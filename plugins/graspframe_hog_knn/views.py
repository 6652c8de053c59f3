"""Random view parameters and the rendering of one view of the hand holding its object.

A view: the human hand in one of the six grasp postures (between open and closed, with
joint noise) holding the grasp's default object (placed by `reference_placement`),
scaled to a random hand size, seen by a camera from a random direction, under random
lighting, with a random skin tone, object colour and background.

Orientation model: the object stands roughly upright in a world with z up (tilted by up
to `tilt_deg` about a random horizontal axis); the camera looks at it from an elevation
(positive = from above, looking down) and any azimuth, with a small roll about its
optical axis. The label is R_camera_palm, the human palm frame in the camera frame
(OpenCV camera axes: x right, y down, z forward).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from graspframe.common.grasps import HumanGrasp
from graspframe.common.transforms import R_from_axis_angle
from graspframe.hal.objects import ObjectDescription
from graspframe.pictures.rasteriser import Camera, Lighting, Renderer, composite
from graspframe_hog_knn.hand_scene import HandModel, Mesh, T_palm_object, object_mesh
from graspframe_hog_knn.segmentation import skin_pixels

GRASPS = tuple(HumanGrasp)

# Skin albedo RGB [0, 1], light to dark; a view interpolates between two neighbours.
SKIN_TONES = np.array(
    [
        [0.96, 0.80, 0.69],
        [0.92, 0.72, 0.58],
        [0.84, 0.62, 0.47],
        [0.74, 0.52, 0.37],
        [0.60, 0.40, 0.27],
        [0.45, 0.29, 0.19],
    ]
)
# Object albedo RGB [0, 1]: colours that are not skin.
OBJECT_COLOURS = np.array(
    [
        [0.15, 0.30, 0.80],
        [0.20, 0.60, 0.25],
        [0.10, 0.55, 0.60],
        [0.45, 0.25, 0.70],
        [0.50, 0.50, 0.52],
        [0.90, 0.90, 0.92],
        [0.12, 0.12, 0.14],
        [0.85, 0.85, 0.20],
    ]
)


@dataclass(frozen=True)
class ViewDistribution:
    """Ranges the view parameters are drawn from (uniformly). Angles [deg], hand_scale
    relative to the 190 mm model hand, closure 0 = open posture, 1 = closed targets."""

    name: str
    hand_scale: tuple[float, float] = (0.88, 1.12)
    elevation_deg: tuple[float, float] = (-20.0, 80.0)
    roll_deg: float = 25.0
    tilt_deg: float = 25.0
    closure: tuple[float, float] = (0.35, 0.75)
    posture_noise_deg: float = 4.0
    ambient: tuple[float, float] = (0.35, 0.65)
    light_tint: float = 0.08
    background: str = "blobs"
    image_noise: float = 3.0  # [grey levels] sensor noise sigma
    fov_x_deg: float = 40.0
    fill: tuple[float, float] = (0.7, 0.95)  # scene radius / image half-width


TRAIN = ViewDistribution("train")
# Held out: other hand sizes (smaller and larger), lighting, backgrounds and noise.
HELD_OUT = ViewDistribution(
    "held_out",
    hand_scale=(0.84, 1.16),
    ambient=(0.3, 0.7),
    light_tint=0.12,
    background="stripes",
    image_noise=5.0,
    fill=(0.55, 0.9),
)
DISTRIBUTIONS = {d.name: d for d in (TRAIN, HELD_OUT)}


@dataclass(frozen=True)
class ViewParams:
    """Everything that determines one rendered view (see ViewDistribution)."""

    grasp: HumanGrasp
    R_camera_palm: NDArray[np.float64]
    hand_scale: float
    q: dict[str, float]
    skin_rgb: NDArray[np.float64]
    object_rgb: NDArray[np.float64]
    lighting: Lighting
    fill: float
    offset: NDArray[np.float64]  # image-centre offset, share of the half-width
    background_seed: int
    distribution: ViewDistribution


@dataclass(frozen=True)
class RenderedView:
    """A rendered image with its exact labels: T_camera_palm (4x4, [m]) and the camera."""

    image: NDArray[np.uint8]
    grasp: HumanGrasp
    T_camera_palm: NDArray[np.float64]
    camera: Camera


def R_world_camera_looking(
    elevation: float, azimuth: float, roll: float = 0.0
) -> NDArray[np.float64]:
    """OpenCV camera axes in a z-up world for a camera looking down by `elevation` [rad]
    towards the target from `azimuth` [rad], rolled by `roll` [rad] about its axis."""
    to_target = -np.array(
        [
            np.cos(elevation) * np.cos(azimuth),
            np.cos(elevation) * np.sin(azimuth),
            np.sin(elevation),
        ]
    )
    x = np.cross(to_target, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    y = np.cross(to_target, x)
    R = np.column_stack([x, y, to_target])
    return R @ R_from_axis_angle([0.0, 0.0, 1.0], roll)


@functools.cache
def _object_frames() -> dict[HumanGrasp, tuple[ObjectDescription, NDArray[np.float64]]]:
    return {g: T_palm_object(g) for g in GRASPS}


def sample_view(
    rng: np.random.Generator, grasp: HumanGrasp, hand: HandModel, dist: ViewDistribution
) -> ViewParams:
    """Draw one view of `grasp` from the distribution `dist`."""
    _, T_palm_obj = _object_frames()[grasp]
    R_palm_obj = T_palm_obj[:3, :3]
    R_world_obj = np.eye(3)
    tilt = np.radians(dist.tilt_deg) * np.sqrt(rng.uniform())
    tilt_axis = rng.uniform(0, 2 * np.pi)
    R_world_obj = R_from_axis_angle([np.cos(tilt_axis), np.sin(tilt_axis), 0.0], tilt)
    R_world_palm = R_world_obj @ R_palm_obj.T
    R_world_camera = R_world_camera_looking(
        np.radians(rng.uniform(*dist.elevation_deg)),
        rng.uniform(-np.pi, np.pi),
        np.radians(rng.uniform(-dist.roll_deg, dist.roll_deg)),
    )
    limits = hand.limits()
    q = hand.posture_q(grasp, rng.uniform(*dist.closure))
    noise = np.radians(dist.posture_noise_deg)
    q = {n: float(np.clip(v + rng.normal(0, noise), *limits[n])) for n, v in q.items()}
    i = rng.integers(len(SKIN_TONES) - 1)
    skin = SKIN_TONES[i] + rng.uniform() * (SKIN_TONES[i + 1] - SKIN_TONES[i])
    tint = 1.0 + rng.uniform(-dist.light_tint, dist.light_tint, 3)
    direction = rng.normal(size=3)
    direction[2] = -abs(direction[2]) - 0.3  # lit from the camera's side
    lighting = Lighting(
        light_dir=tuple(direction / np.linalg.norm(direction)),
        light_colour=tuple(tint / tint.max()),
        ambient=float(rng.uniform(*dist.ambient)),
        specular=float(rng.uniform(0.0, 0.15)),
    )
    return ViewParams(
        grasp=grasp,
        R_camera_palm=R_world_camera.T @ R_world_palm,
        hand_scale=float(rng.uniform(*dist.hand_scale)),
        q=q,
        skin_rgb=skin,
        object_rgb=OBJECT_COLOURS[rng.integers(len(OBJECT_COLOURS))],
        lighting=lighting,
        fill=float(rng.uniform(*dist.fill)),
        offset=rng.uniform(-0.1, 0.1, 2),
        background_seed=int(rng.integers(2**31)),
        distribution=dist,
    )


def scene_in_palm(hand: HandModel, params: ViewParams) -> tuple[Mesh, NDArray[np.float32]]:
    """Hand and object triangles in the palm frame [m] and their per-vertex albedo."""
    obj, T_palm_obj = _object_frames()[params.grasp]
    s = params.hand_scale
    hand_mesh = hand.mesh(params.q)
    T = T_palm_obj.copy()
    T[:3, 3] *= s  # the object sits where the scaled hand holds it
    obj_mesh = object_mesh(obj).transformed(T)
    positions = np.concatenate([hand_mesh.positions * s, obj_mesh.positions])
    normals = np.concatenate([hand_mesh.normals, obj_mesh.normals])
    albedo = np.concatenate(
        [
            np.tile(params.skin_rgb, (len(hand_mesh.positions), 1)),
            np.tile(params.object_rgb, (len(obj_mesh.positions), 1)),
        ]
    ).astype(np.float32)
    return Mesh(positions.astype(np.float32), normals), albedo


def background(rng: np.random.Generator, style: str, width: int, height: int):
    """A skin-free background image (BGR uint8): 'blobs' (gradient and ellipses) or
    'stripes' (stripes and checks). Retried until no pixel passes the skin test."""
    import cv2

    for _ in range(20):
        colours = _non_skin_colours(rng, 4)
        if style == "blobs":
            t = np.linspace(0, 1, width)[None, :, None] * np.ones((height, 1, 1))
            if rng.uniform() < 0.5:
                t = np.linspace(0, 1, height)[:, None, None] * np.ones((1, width, 1))
            img = (1 - t) * colours[0] + t * colours[1]
            for c in colours[2:]:
                centre = (int(rng.uniform(0, width)), int(rng.uniform(0, height)))
                axes = (int(rng.uniform(0.05, 0.3) * width), int(rng.uniform(0.05, 0.3) * height))
                cv2.ellipse(img, centre, axes, rng.uniform(0, 180), 0, 360, c.tolist(), -1)
        else:
            angle = rng.uniform(0, np.pi)
            period = rng.uniform(0.05, 0.25) * width
            yy, xx = np.mgrid[0:height, 0:width]
            phase = (xx * np.cos(angle) + yy * np.sin(angle)) / period
            band = (np.floor(phase) % 2).astype(int)
            if rng.uniform() < 0.5:
                phase2 = (-xx * np.sin(angle) + yy * np.cos(angle)) / period
                band = band ^ (np.floor(phase2) % 2).astype(int)
            img = np.where(band[..., None] == 1, colours[0], colours[1])
            img = img.astype(np.float64)
        out = np.clip(img, 0, 255).astype(np.uint8)
        if not skin_pixels(out).any():
            return out
    grey = rng.uniform(40, 220)
    return np.full((height, width, 3), grey, np.uint8)


def _non_skin_colours(rng: np.random.Generator, n: int) -> NDArray[np.float64]:
    out: list[NDArray[np.float64]] = []
    while len(out) < n:
        c = rng.uniform(0, 255, 3)
        if not skin_pixels(c.astype(np.uint8)[None, None, :]).any():
            out.append(c)
    return np.array(out)


def _bounding_sphere(positions: NDArray[np.float32]) -> tuple[NDArray[np.floating], float]:
    """Centre of the axis-aligned bounding box of (N, 3) points and the largest distance
    of a point from it [m]. Column by column: numpy reduces an (N, 3) array along axis 0
    about 20 times slower than its three columns one by one."""
    columns = [positions[:, i] for i in range(3)]
    lo = np.array([c.min() for c in columns], dtype=positions.dtype)
    hi = np.array([c.max() for c in columns], dtype=positions.dtype)
    centre = (lo + hi) / 2
    offsets = positions - centre
    return centre, float(np.sqrt(np.einsum("ij,ij->i", offsets, offsets).max()))


def render_view(renderer: Renderer, hand: HandModel, params: ViewParams, size: int) -> RenderedView:
    """Render `params` to a size x size BGR image with its exact palm pose."""
    dist = params.distribution
    camera = Camera.from_fov(size, size, dist.fov_x_deg)
    mesh, albedo = scene_in_palm(hand, params)
    centre, radius = _bounding_sphere(mesh.positions)
    half_angle = np.radians(dist.fov_x_deg) / 2
    depth = radius / (np.tan(half_angle) * params.fill)
    lateral = params.offset * depth * np.tan(half_angle)
    p_camera_centre = np.array([lateral[0], lateral[1], depth])
    R = params.R_camera_palm
    p_camera_palm = p_camera_centre - R @ centre
    positions = (mesh.positions @ R.T + p_camera_palm).astype(np.float32)
    normals = (mesh.normals @ R.T).astype(np.float32)
    fg, alpha = renderer.render(camera, positions, normals, albedo, params.lighting)
    rng = np.random.default_rng(params.background_seed)
    bg = background(rng, dist.background, size, size)
    image = composite(fg, alpha, bg)
    noisy = image.astype(np.float32) + rng.normal(0, dist.image_noise, image.shape)
    image = np.clip(noisy + 0.5, 0, 255).astype(np.uint8)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p_camera_palm
    return RenderedView(image=image, grasp=params.grasp, T_camera_palm=T, camera=camera)
