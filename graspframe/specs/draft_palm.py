"""The palm frame and the palm pad a hand draft puts on a URDF's palm (see
graspframe/specs/draft.py): +z the direction the fingers close towards, +x along them,
the origin on the palm's collision surface where the palm is solid below it; the pad the
palm surface there, cut back clear of the fingers."""

from __future__ import annotations

import contextlib
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from graspframe.specs.draft_kinematics import (
    Axes,
    DraftFinger,
    Joints,
    Kinematics,
    closing_direction,
    tip_position,
)

PALM_SURFACE_LAYER = 0.003  # [m] palm points this close to the palm height form its pad
PAD_MARGIN = 0.005  # [m] the pad stays this far inside the palm surface's outline
MIN_PAD_SIDE = 0.01  # [m]


def palm_frame(
    fingers: Mapping[str, DraftFinger],
    thumb: str | None,
    joints: Joints,
    kin: Kinematics,
    axes: Axes,
    rest: Mapping[str, float],
    palm_links: Sequence[str],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(T_palmlink_palm, pad centre [m] in the palm frame, pad size [m])."""
    kin.place(rest)
    others = [f for n, f in fingers.items() if n != thumb] or list(fingers.values())
    closing = np.mean([closing_direction(f, joints, kin, axes) for f in others], axis=0)
    roots = np.array([kin.T(joints[f.joints[0]].child)[:3, 3] for f in fingers.values()])
    tips = np.array([tip_position(f, kin) for f in others])
    along = np.mean(
        tips - np.array([kin.T(joints[f.joints[0]].child)[:3, 3] for f in others]), axis=0
    )
    every = np.mean([closing_direction(f, joints, kin, axes) for f in fingers.values()], axis=0)
    if np.linalg.norm(every) < 0.3:  # the fingers close against each other: a gripper
        z = along / max(np.linalg.norm(along), 1e-12)
        x_guess = tips[0] - roots.mean(axis=0)
    else:
        # The normal of the plane the extended fingers' curling joints lie in,
        # turned the way they close; the thumb's points join when the others are a line.
        def chain_points(chosen: Sequence[DraftFinger]) -> NDArray[np.float64]:
            return np.array(
                [kin.T(joints[j].child)[:3, 3] for f in chosen for j in f.flexion]
            ).reshape(-1, 3)

        def planar(points: NDArray[np.float64]) -> bool:
            if len(points) < 3:
                return False
            spread = np.linalg.svd(points - points.mean(axis=0), compute_uv=False)
            return bool(spread[1] >= 0.1 * spread[0])

        points = chain_points(others)
        if not planar(points):
            points = chain_points(list(fingers.values()))
        if planar(points):
            normal = np.linalg.svd(points - points.mean(axis=0))[2][2]
            z = normal if float(normal @ closing) >= 0 else -normal
        else:  # one finger in a line: the way it closes
            z = closing / np.linalg.norm(closing)
        x_guess = along
    x = x_guess - (x_guess @ z) * z
    if np.linalg.norm(x) < 1e-6:
        x = np.cross(z, [1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.cross(z, [0.0, 1.0, 0.0])
    x = x / np.linalg.norm(x)
    y = np.cross(z, x)
    R = np.column_stack([x, y, z])
    points = kin.link_points(palm_links)
    centre = roots.mean(axis=0)
    if len(points):
        local = (points - centre) @ R
        near = local[np.hypot(local[:, 0], local[:, 1]) <= max(0.03, np.ptp(local[:, 0]) / 2)]
        height = _surface_height(near if len(near) else local)
        # the origin: the middle of the palm surface (its points within 3 mm of the
        # height), on it
        layer = local[local[:, 2] >= height - PALM_SURFACE_LAYER]
        lo, hi = layer[:, :2].min(axis=0) + PAD_MARGIN, layer[:, :2].max(axis=0) - PAD_MARGIN
        size = np.maximum(hi - lo, MIN_PAD_SIDE)
        middle = (layer[:, :2].min(axis=0) + layer[:, :2].max(axis=0)) / 2
        middle = _solid_below(
            kin, palm_links, centre, R, height, middle, local[:, :2].min(axis=0),
            local[:, :2].max(axis=0),
        )  # fmt: skip
        lo, hi = _clear_of_fingers(kin, fingers, thumb, joints, centre, R, height, middle, lo, hi)
        size = np.maximum(hi - lo, MIN_PAD_SIDE)
        origin = centre + R @ np.array([middle[0], middle[1], height])
        pad_centre = np.array(
            [(lo[0] + hi[0]) / 2 - middle[0], (lo[1] + hi[1]) / 2 - middle[1], 0.0]
        )
    else:
        origin, size, pad_centre = centre, np.array([0.04, 0.04]), np.zeros(3)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, origin
    return T, pad_centre, np.array([size[0], size[1], 0.002])


SURFACE_SHARE = 0.03  # of the palm's outline: a layer covering less is a bump, not the palm
SURFACE_STEP = 0.0005  # [m] the heights tried, from the highest point down


def _surface_height(local: NDArray[np.float64]) -> float:
    """[m] The palm surface's height over its points (palm frame): the highest whose
    layer (the points within PALM_SURFACE_LAYER below it) covers SURFACE_SHARE of the
    palm's outline seen along its normal. On most palms that is the highest point; a
    small box standing proud of the palm (the Shadow hand's thenar boxes, 10 mm over
    the palm by the wrist) would otherwise put the palm frame on it, at the palm's
    corner."""
    outline = _area(local[:, :2])
    heights = local[:, 2]
    height = float(heights.max())
    while True:
        layer = local[heights >= height - PALM_SURFACE_LAYER]
        if _area(layer[:, :2]) >= SURFACE_SHARE * outline:
            return height
        lower = heights[heights < height - SURFACE_STEP]
        if not len(lower):
            return float(heights.max())
        height = float(lower.max())


def _area(points: NDArray[np.float64]) -> float:
    """[m^2] The area of the points' convex hull (0 for fewer than three or a line)."""
    from scipy.spatial import ConvexHull, QhullError

    if len(points) < 3:
        return 0.0
    try:
        return float(ConvexHull(points).volume)  # a 2-D hull's volume is its area
    except QhullError:
        return 0.0


PROBE_DEPTH = 0.0105  # [m] the palm must be solid this far below its frame's origin
PROBE_STEP = 0.003  # [m] the grid of origins tried
PAD_CLEARANCE = 0.002  # [m] finger shapes stay this far from the pad
CURL_FRACTIONS = (0.0, 0.25, 0.5, 1.0)
PLACING_FRACTIONS = (0.0, 0.5, 1.0)  # of a placing joint's range, lower to upper


class _Solids:
    """The collision shapes of some links as convex hulls (half-space equations), in the
    palm link's frame: which points lie inside, and surface samples."""

    def __init__(self, kin: Kinematics, links: Sequence[str]):
        from scipy.spatial import ConvexHull

        from graspframe.robot_models.shapes import geometry_mesh

        T_palm_root = np.linalg.inv(kin.collision.T_root_frame(kin.palm_link))
        wanted = set(links)
        self.equations, samples = [], []
        for link, shape, T_root_shape in kin.collision.shapes():
            if link not in wanted:
                continue
            mesh = geometry_mesh(shape)
            if mesh is None:
                continue
            T = T_palm_root @ T_root_shape
            vertices = np.asarray(mesh.vertices) @ T[:3, :3].T + T[:3, 3]
            with contextlib.suppress(Exception):  # a flat piece: no volume to be inside
                self.equations.append(ConvexHull(vertices).equations)
            mesh.apply_transform(T)
            samples.append(vertices)
            samples.append(np.asarray(mesh.sample(400, seed=0)))
        self.samples = np.vstack(samples) if samples else np.zeros((0, 3))

    def inside(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        hit = np.zeros(len(points), dtype=bool)
        for eq in self.equations:
            hit |= np.all(points @ eq[:, :3].T + eq[:, 3] <= 1e-9, axis=1)
        return hit


def _solid_below(
    kin: Kinematics,
    palm_links: Sequence[str],
    centre: NDArray[np.float64],
    R: NDArray[np.float64],
    height: float,
    middle: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The in-plane point nearest `middle` (palm-frame x, y [m]) of the palm surface
    below which the palm is solid to PROBE_DEPTH (the palm frame's contract)."""
    solids = _Solids(kin, palm_links)
    xs = np.arange(lo[0], hi[0] + 1e-9, PROBE_STEP)
    ys = np.arange(lo[1], hi[1] + 1e-9, PROBE_STEP)
    grid = np.array([(x, y) for x in xs for y in ys]).reshape(-1, 2)
    below = np.column_stack([grid, np.full(len(grid), height - PROBE_DEPTH)])
    above = np.column_stack([grid, np.full(len(grid), height + 0.001)])
    solid = solids.inside(centre + below @ R.T) & ~solids.inside(centre + above @ R.T)
    if not solid.any():
        return middle
    chosen = grid[solid]
    return chosen[int(np.argmin(np.linalg.norm(chosen - middle, axis=1)))]


def _clear_of_fingers(
    kin: Kinematics,
    fingers: Mapping[str, DraftFinger],
    thumb: str | None,
    joints: Joints,
    centre: NDArray[np.float64],
    R: NDArray[np.float64],
    height: float,
    middle: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The pad's (lo, hi) corners (palm-frame x, y [m]) cut back, edge by edge, until no
    finger shape, at rest or curled (CURL_FRACTIONS of the way closed), the thumb at
    any placing (PLACING_FRACTIONS of its joints' ranges), comes within
    PAD_CLEARANCE of it (the pad is 2 mm thick on the palm surface); the pad keeps
    `middle` inside."""
    finger_links = [link for f in fingers.values() for link in f.links]
    rest = {j: v for j, v in kin.collision_q().items()}
    closed = dict(rest)
    for finger in fingers.values():
        for name in finger.flexion:
            joint = joints[name]
            closed[name] = joint.upper if finger.closing_sign[name] > 0 else joint.lower
    # the thumb turns into opposition over the palm (the other fingers' spread keeps
    # them at its edge, and sweeping it would leave a Barrett hand a strip of a pad)
    placing = list(fingers[thumb].placing) if thumb is not None and thumb in fingers else []
    samples = []
    # the fingers as they curl (their knuckles turn near the pad), the thumb's placing
    # joints at their lower limits, their middles and their upper limits
    for t in CURL_FRACTIONS:
        curled = {j: rest[j] + t * (closed[j] - rest[j]) for j in rest}
        for p in PLACING_FRACTIONS:
            for name in placing:
                curled[name] = joints[name].lower + p * (joints[name].upper - joints[name].lower)
            kin.place(curled)
            samples.append(_Solids(kin, finger_links).samples)
    kin.place(rest)
    points = (np.vstack(samples) - centre) @ R
    near = points[np.abs(points[:, 2] - height) <= 0.001 + PAD_CLEARANCE]
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    while True:
        inside = near[
            np.all(near[:, :2] >= lo - PAD_CLEARANCE, axis=1)
            & np.all(near[:, :2] <= hi + PAD_CLEARANCE, axis=1)
        ]
        if len(inside) == 0 or np.any(hi - lo <= MIN_PAD_SIDE):
            break
        p = inside[0, :2]
        # move the edge that loses the least pad past the point, keeping the middle in
        cuts = []
        for axis in (0, 1):
            if p[axis] >= middle[axis]:
                cuts.append((hi[axis] - (p[axis] - PAD_CLEARANCE), axis, True))
            else:
                cuts.append(((p[axis] + PAD_CLEARANCE) - lo[axis], axis, False))
        before = (lo.copy(), hi.copy())
        for _, axis, upper in sorted(cuts):
            if upper:
                hi[axis] = max(middle[axis] + MIN_PAD_SIDE / 2, p[axis] - PAD_CLEARANCE - 1e-4)
            else:
                lo[axis] = min(middle[axis] - MIN_PAD_SIDE / 2, p[axis] + PAD_CLEARANCE + 1e-4)
            if not (np.array_equal(lo, before[0]) and np.array_equal(hi, before[1])):
                break
        else:
            break  # the point lies over the middle itself: the pad cannot clear it
    return lo, hi


DORSAL_PLATE_SIDE = 0.064  # [m] the square plate a drafted dorsal mounting proposes
DORSAL_PLATE_THICKNESS = 0.015  # [m]


def back_of_palm(
    kin: Kinematics, T_palmlink_palm: NDArray[np.float64], links: Sequence[str]
) -> float | None:
    """[m] how far behind the palm frame's origin (along its -z) the hand ends within the
    square of a dorsal plate centred behind it (DORSAL_PLATE_SIDE): the plate's face goes
    there. The hand placed at rest; None when no shape of `links` lies in that square."""
    points = kin.link_points(links)
    if not len(points):
        return None
    T_palm_palmlink = np.linalg.inv(T_palmlink_palm)
    local = points @ T_palm_palmlink[:3, :3].T + T_palm_palmlink[:3, 3]
    behind = local[np.all(np.abs(local[:, :2]) <= DORSAL_PLATE_SIDE / 2, axis=1)]
    if not len(behind):
        return None
    return float(max(-behind[:, 2].min(), 0.0))


FLANGE_REACH = 0.06  # [m] from the flange's axis: the arm's last link lies within this


def behind_the_flange(kin: Kinematics, root_link: str) -> float:
    """[m] how far the hand at rest reaches behind its root link's frame (below its
    z = 0 plane, within FLANGE_REACH of its z axis): bolted there straight on an arm's
    flange, that much of the hand would lie in the arm's last link. 0 when none does."""
    T_root_palmlink = kin.collision.T_root_frame(kin.palm_link)
    T_rootlink_root = np.linalg.inv(kin.collision.T_root_frame(root_link))
    T = T_rootlink_root @ T_root_palmlink
    points = kin.link_points([link for link, _s, _T in kin.collision.shapes()])
    local = points @ T[:3, :3].T + T[:3, 3]
    near = local[np.hypot(local[:, 0], local[:, 1]) <= FLANGE_REACH]
    return float(max(-near[:, 2].min(), 0.0)) if len(near) else 0.0
