"""The geometry of a mesh object: its frame, rest pose, convex pieces and mass properties.

Computed once per process and mesh (kept in memory), from the mesh file (the visual
mesh, e.g. a scan) and its convex pieces (graspframe/model_files/convex.py), all in metres:

- Solid: the union of the convex pieces. A scanned visual mesh is usually not
  watertight, so its own volume and centroid are unreliable; the pieces are closed, but
  they overlap, so their volumes cannot simply be added. The union is sampled on a grid
  of VOXELS_ACROSS cells across the object's largest extent (about 1 mm for a 10 cm
  object), centred on the pieces' bounding box: each convex piece marks, column by
  column, the cells whose centres lie inside it, and the marked cells are counted once.
  Volume, centroid and inertia are those of the marked cells at uniform density (each
  cell a small cube). On the six YCB scans of the tests, halving the cell changes the
  centroid by less than 0.1 mm and the inertia by less than 1 %. A single piece (a
  convex mesh) is measured exactly instead (trimesh).
- Object frame: origin at that centroid. Its axes are the mesh file's axes when the mesh
  stands stably as the file has it (z up: the centroid lies over its support polygon,
  the hull of the pieces' points within SUPPORT_TOLERANCE of their lowest point, by at
  least SUPPORT_MARGIN); otherwise the rest pose is the most probable stable pose of
  the pieces' convex hull (trimesh.poses.compute_stable_poses) and the object frame's z
  is up in it. Either way the object rests on the table with the identity orientation.
  `T_mesh_object` is the object frame in the mesh file's frame.
- Symmetric about z: the horizontal extent of the visual mesh from the centroid
  (its support function along 72 horizontal directions) varies by less than
  SYMMETRY_TOLERANCE of its mean. A scanned can or ball passes (the YCB soup can varies
  by 5 %, the tennis ball by 4 %); a bottle, a mug with its handle, a brick do not
  (46 % and more). Only a symmetric object may be grasped turned about its axis.
"""

from __future__ import annotations

import functools
import hashlib
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import ArrayLike, NDArray

from graspframe.common.transforms import inv_T, make_T, transform_points
from graspframe.model_files.convex import ConvexPieces, convex_pieces, load_mesh

VOXELS_ACROSS = 100  # grid cells across the largest extent for the mass properties
SUPPORT_TOLERANCE = 0.001  # [m] points this close to the lowest one carry the object
SUPPORT_MARGIN = 0.001  # [m] the centroid must lie this far inside the support polygon
SYMMETRY_TOLERANCE = 0.10  # relative spread of the horizontal extent of a symmetric mesh
SYMMETRY_DIRECTIONS = 72
# (modification time [ns], size [B]) of each file: what identifies their content cheaply
Stamp = tuple[tuple[int, int], ...]


@dataclass(frozen=True)
class MeshGeometry:
    """A mesh object's geometry (see the module docstring).

    T_mesh_object: 4x4 pose of the object frame (centroid; z up at rest) in the mesh
        file's frame [m].
    convex: the convex pieces in the mesh file's frame, with their cache files.
    pieces: the same pieces in the object frame [m].
    volume: [m^3] of the union of the pieces.
    inertia_per_mass: 3x3 inertia about the centroid, object frame, per kg [m^2]
        (times the mass: [kg m^2]).
    upright_as_scanned: the rest pose is the mesh file's own orientation.
    symmetric_about_z: see the module docstring.
    content_sha256: of the mesh file, the pieces file and the scale (cache keys).
    """

    T_mesh_object: NDArray[np.float64]
    convex: ConvexPieces
    pieces: tuple[trimesh.Trimesh, ...]
    volume: float
    inertia_per_mass: NDArray[np.float64]
    upright_as_scanned: bool
    symmetric_about_z: bool
    content_sha256: str

    @functools.cached_property
    def points(self) -> NDArray[np.float64]:
        """(n, 3) every piece's vertices in the object frame [m]."""
        return np.concatenate([np.asarray(p.vertices, dtype=float) for p in self.pieces])

    @property
    def bounds(self) -> NDArray[np.float64]:
        """(2, 3) lowest and highest corner of the pieces in the object frame [m]."""
        return np.array([self.points.min(axis=0), self.points.max(axis=0)])

    @functools.cached_property
    def fingerprint(self) -> str:
        """SHA-256 of what the simulator is given: the files' content, the object frame,
        the inertia and every piece (cache keys of results that depend on them)."""
        digest = hashlib.sha256(self.content_sha256.encode())
        digest.update(np.ascontiguousarray(self.T_mesh_object, dtype=float).tobytes())
        digest.update(np.ascontiguousarray(self.inertia_per_mass, dtype=float).tobytes())
        for piece in self.pieces:
            digest.update(np.ascontiguousarray(piece.vertices, dtype=float).tobytes())
        return digest.hexdigest()

    def extent_along(self, n_object: ArrayLike) -> float:
        """[m] support function of the pieces: the farthest any of them reaches from the
        centroid along the unit direction n_object (object frame)."""
        n = np.asarray(n_object, dtype=float)
        return float((self.points @ (n / np.linalg.norm(n))).max())


@dataclass(frozen=True)
class _Solid:
    volume: float
    centroid: NDArray[np.float64]
    inertia_per_mass: NDArray[np.float64]


def union_mass_properties(
    pieces: Sequence[trimesh.Trimesh], cells_across: int = VOXELS_ACROSS
) -> _Solid:
    """Volume [m^3], centroid [m] and inertia per mass about it [m^2] of the union of
    convex pieces, sampled on a grid (see the module docstring); one piece exactly."""
    if len(pieces) == 1 and pieces[0].is_volume:
        piece = pieces[0]
        return _Solid(
            float(piece.volume),
            np.asarray(piece.center_mass, dtype=float),
            np.asarray(piece.moment_inertia, dtype=float) / float(piece.volume),
        )
    points = np.concatenate([np.asarray(p.vertices, dtype=float) for p in pieces])
    low, high = points.min(axis=0), points.max(axis=0)
    pitch = float((high - low).max()) / cells_across
    counts = np.maximum(1, np.ceil((high - low) / pitch).astype(int))
    # The grid centred on the pieces' bounding box: it overhangs both sides equally.
    start = (low + high) / 2 - counts * pitch / 2
    centres = [start[i] + pitch * (np.arange(counts[i]) + 0.5) for i in range(3)]
    inside = np.zeros(counts, dtype=bool)
    for piece in pieces:
        _mark_inside(piece, centres, inside)
    index = np.nonzero(inside)
    cells = np.stack([centres[axis][index[axis]] for axis in range(3)], axis=1)
    if len(cells) == 0:  # pieces thinner than a cell: take their vertices as the solid
        cells = points
    centroid = cells.mean(axis=0)
    r = cells - centroid
    # Point masses at the cell centres plus each cell's own inertia (a cube: pitch^2/6).
    inertia = (np.eye(3) * (r * r).sum(axis=1).mean() - r.T @ r / len(r)) + np.eye(3) * pitch**2 / 6
    return _Solid(len(index[0]) * pitch**3, centroid, inertia)


def _mark_inside(
    piece: trimesh.Trimesh, centres: list[NDArray[np.float64]], inside: NDArray[np.bool_]
) -> None:
    """Set the cells of `inside` whose centres lie in the convex piece, column by column
    along z: each column's entry and exit heights follow from the piece's face planes."""
    low, high = piece.bounds
    span = []
    for axis in range(3):
        first = int(np.searchsorted(centres[axis], low[axis]))
        last = int(np.searchsorted(centres[axis], high[axis], side="right"))
        if first >= last:
            return
        span.append(slice(first, last))
    x, y = np.meshgrid(centres[0][span[0]], centres[1][span[1]], indexing="ij")
    normals = np.asarray(piece.face_normals, dtype=float)  # outward
    offsets = -np.einsum("ij,ij->i", normals, np.asarray(piece.triangles[:, 0]))
    # Inside: n . p + offset <= 0 for every face, i.e. n_z z <= rest.
    rest = -(offsets + x[..., None] * normals[:, 0] + y[..., None] * normals[:, 1])
    up, down = normals[:, 2] > 1e-12, normals[:, 2] < -1e-12
    side = ~(up | down)
    z_high = np.min(rest[..., up] / normals[up, 2], axis=-1) if up.any() else np.inf
    z_low = np.max(rest[..., down] / normals[down, 2], axis=-1) if down.any() else -np.inf
    column = np.all(rest[..., side] >= 0, axis=-1) if side.any() else True
    z = centres[2][span[2]]
    inside[span[0], span[1], span[2]] |= (
        np.asarray(column)[..., None]
        & (z >= np.asarray(z_low)[..., None])
        & (z <= np.asarray(z_high)[..., None])
    )


def rests_upright(points: NDArray[np.float64], centroid: NDArray[np.float64]) -> bool:
    """True when the points' lowest ones (within SUPPORT_TOLERANCE) form a support
    polygon with the centroid at least SUPPORT_MARGIN inside it (seen from above)."""
    from scipy.spatial import ConvexHull, QhullError

    support = points[points[:, 2] <= points[:, 2].min() + SUPPORT_TOLERANCE][:, :2]
    try:
        equations = ConvexHull(support).equations  # n . p + d <= 0 inside
    except (QhullError, ValueError):  # a point or a line: no area to stand on
        return False
    margin = -float((equations[:, :2] @ centroid[:2] + equations[:, 2]).max())
    return margin >= SUPPORT_MARGIN


def rest_rotation(
    points: NDArray[np.float64], centroid: NDArray[np.float64]
) -> tuple[NDArray[np.float64], bool]:
    """(R_rest_mesh, upright_as_scanned): the rotation taking the mesh frame to its rest
    pose on the table (identity when it stands as scanned), see the module docstring."""
    if rests_upright(points, centroid):
        return np.eye(3), True
    hull = trimesh.convex.convex_hull(points)
    transforms, probabilities = trimesh.poses.compute_stable_poses(hull, center_mass=centroid)
    return np.asarray(transforms[int(np.argmax(probabilities))])[:3, :3], False


def symmetric_about_z(points_object: NDArray[np.float64]) -> bool:
    """See the module docstring; points in the object frame [m]."""
    angles = np.linspace(0.0, 2.0 * math.pi, SYMMETRY_DIRECTIONS, endpoint=False)
    directions = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    extent = (points_object[:, :2] @ directions.T).max(axis=0)
    return bool(extent.max() - extent.min() <= SYMMETRY_TOLERANCE * extent.mean())


def _sha256(paths: Sequence[Path | None], scale: Sequence[float]) -> str:
    digest = hashlib.sha256()
    for path in paths:
        digest.update(b"-" if path is None else Path(path).read_bytes())
    digest.update(repr([float(s) for s in scale]).encode())
    return digest.hexdigest()


@functools.lru_cache(maxsize=32)
def _geometry(
    mesh_path: Path, given_pieces: Path | None, scale: tuple[float, float, float], _stamp: Stamp
) -> MeshGeometry:
    convex = convex_pieces(mesh_path, scale, given_pieces)
    solid = union_mass_properties(convex.pieces)
    R_rest_mesh, upright = rest_rotation(convex.vertices, solid.centroid)
    T_object_mesh = make_T(R_rest_mesh, -R_rest_mesh @ solid.centroid)
    pieces = tuple(piece.copy().apply_transform(T_object_mesh) for piece in convex.pieces)
    visual = transform_points(T_object_mesh, load_mesh(mesh_path, scale).vertices)
    return MeshGeometry(
        T_mesh_object=inv_T(T_object_mesh),
        convex=convex,
        pieces=pieces,
        volume=solid.volume,
        inertia_per_mass=R_rest_mesh @ solid.inertia_per_mass @ R_rest_mesh.T,
        upright_as_scanned=upright,
        symmetric_about_z=symmetric_about_z(np.asarray(visual).reshape(-1, 3)),
        content_sha256=_sha256((mesh_path, given_pieces), scale),
    )


def _stamp(paths: Sequence[Path | None]) -> Stamp:
    """What identifies the files' content cheaply (a changed file is read again)."""
    stamps = []
    for path in paths:
        if path is not None:
            stat = Path(path).stat()
            stamps.append((stat.st_mtime_ns, stat.st_size))
    return tuple(stamps)


def mesh_geometry(
    mesh_path: Path, given_pieces: Path | None = None, scale: Sequence[float] = (1.0, 1.0, 1.0)
) -> MeshGeometry:
    """The geometry of a mesh object, computed once per process for each file content."""
    mesh_path = Path(mesh_path).resolve()
    given = None if given_pieces is None else Path(given_pieces).resolve()
    s = (float(scale[0]), float(scale[1]), float(scale[2]))
    return _geometry(mesh_path, given, s, _stamp((mesh_path, given)))


@functools.lru_cache(maxsize=8)
def _display_mesh(
    mesh_path: Path, scale: tuple[float, float, float], T_mesh_object_key: bytes, _stamp: Stamp
) -> trimesh.Trimesh:
    T_mesh_object = np.frombuffer(T_mesh_object_key).reshape(4, 4)
    mesh = load_mesh(mesh_path, scale)
    mesh.apply_transform(inv_T(T_mesh_object))
    return mesh


def display_mesh(
    geometry: MeshGeometry, mesh_path: Path, scale: Sequence[float]
) -> trimesh.Trimesh:
    """The visual mesh in the object frame [m] (a copy; cached per process)."""
    mesh_path = Path(mesh_path).resolve()
    s = (float(scale[0]), float(scale[1]), float(scale[2]))
    key = np.ascontiguousarray(geometry.T_mesh_object, dtype=float).tobytes()
    return _display_mesh(mesh_path, s, key, _stamp((mesh_path,))).copy()


@functools.lru_cache(maxsize=4)
def _textured_mesh(
    mesh_path: Path, scale: tuple[float, float, float], T_key: bytes, _stamp: Stamp
) -> tuple[trimesh.Trimesh, NDArray[np.uint8]] | None:
    T_object_mesh = inv_T(np.frombuffer(T_key).reshape(4, 4))
    try:
        loaded = trimesh.load(mesh_path, force="mesh", process=False)
        if not isinstance(loaded, trimesh.Trimesh):
            return None
        visual = loaded.visual
        if isinstance(visual, trimesh.visual.TextureVisuals):
            visual = visual.to_color()
        if not isinstance(visual, trimesh.visual.ColorVisuals):
            return None
        colours = np.asarray(visual.vertex_colors, dtype=np.uint8)
    except Exception:  # no texture, or one that cannot be read: geometry only
        return None
    if colours.shape != (len(loaded.vertices), 4):
        return None
    vertices = np.asarray(loaded.vertices, dtype=float) * np.asarray(scale)
    mesh = trimesh.Trimesh(vertices, np.asarray(loaded.faces), process=False)
    mesh.apply_transform(T_object_mesh)
    return mesh, colours


def textured_display_mesh(
    geometry: MeshGeometry, mesh_path: Path, scale: Sequence[float]
) -> tuple[trimesh.Trimesh, NDArray[np.uint8] | None]:
    """(visual mesh in the object frame [m], RGBA colours (n, 4) of its vertices): the
    colours of its texture (or of its vertices) when the file has one, read with its
    material; otherwise the display mesh and None. Slower than `display_mesh` (a texture
    is decoded): for recordings."""
    mesh_path = Path(mesh_path).resolve()
    s = (float(scale[0]), float(scale[1]), float(scale[2]))
    key = np.ascontiguousarray(geometry.T_mesh_object, dtype=float).tobytes()
    found = _textured_mesh(mesh_path, s, key, _stamp((mesh_path,)))
    if found is None:
        return display_mesh(geometry, mesh_path, scale), None
    mesh, colours = found
    return mesh.copy(), colours.copy()
