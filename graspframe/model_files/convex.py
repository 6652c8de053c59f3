"""A mesh file as convex pieces, computed once and cached on disk.

Simulators and collision checkers work on convex shapes: PhysX cooks convex meshes of at
most 255 vertices, coal's GJK works on convex shapes. `convex_pieces` turns a mesh file
(OBJ, STL, DAE, GLB, glTF, PLY; metres after `scale`) into convex pieces, in the mesh file's own
frame, by the first rule that applies:

- `given_pieces`: a file whose connected parts are already convex pieces (e.g. a YCB
  `textured_vhacd.stl`, a V-HACD decomposition merged into one file): split by
  connectivity, each part replaced by its convex hull, slivers (parts whose hull is
  degenerate or holds less than SLIVER_VOLUME_FRACTION of the total volume) dropped.
  Method "given pieces".
- a watertight mesh that is nearly convex (its hull's volume at most
  NEARLY_CONVEX_RATIO times its own): its convex hull. Method "hull".
- anything else: an approximate convex decomposition with CoACD (Wei et al., "Approximate
  Convex Decomposition for 3D Meshes with Collision-Aware Concavity and Tree Search",
  SIGGRAPH 2022), seed 0, concavity threshold COACD_THRESHOLD, a lighter search than its
  defaults (COACD_SEARCH). Method "coacd". This can take minutes on a 16k-face scan,
  hence the cache.

Every piece is a closed convex hull of at most MAX_PIECE_VERTICES vertices (PhysX's own
limit): a hull of more than MIN_KEPT_VERTICES keeps the fewest of its vertices, taken by
farthest-point sampling (first its extreme points along the axes and the diagonals), 64
and then 32 more at a time, whose hull lies within HULL_TOLERANCE (1.5 mm) inside it
(`reduced_hull_vertices`). Then every vertex closer than PLANE_TOLERANCE to the hull of
the others (nearly coplanar with a face of it) is dropped, closest first. The result
lies inside the original hull, an inner approximation; `inner_gap` measures how far the
original reaches outside it: at most 1.45 mm on the Franka Panda's collision meshes
(convex STLs of up to 152 hull vertices, of which 63 to 118 are kept), 1.39 mm on the
LEAP hand's fingertip meshes (thousands of hull vertices, 29 and 31 kept) and 1.35 mm
on the six YCB scans' V-HACD pieces.
PhysX builds its own hull when it cooks a convex mesh and drops the points it finds
within its plane tolerance (0.7 mm) of the hull under construction; with the pieces
simplified here it keeps every vertex of almost every piece (on the six YCB scans it
drops one vertex of 5 of 359 pieces, moving them by at most 1.9 mm; the SAPIEN backend
refuses more than 2.5 mm), so the simulator and the collision checker see the same
pieces, and so do the pictures where they draw the simulated shapes.

The cache: `<GRASPFRAME_CACHE_DIR or ~/.cache/graspframe>/decompositions/<key>/`, the key
the SHA-256 of the decomposed file's bytes and every parameter above. An entry
(graspframe/common/cache.py) holds one OBJ file per piece (`piece_000-<hash>.obj`, ...; loaders
such as a URDF read files) and the method; it is checked whenever it is read, and a
damaged one is rebuilt with a warning naming it.
"""

from __future__ import annotations

import hashlib
import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import NDArray

from graspframe.common.cache import ENTRY_FORMAT, CacheEntry, cache_dir, read_entry, write_entry
from graspframe.common.errors import DescriptionError
from graspframe.common.files import mesh_file

log = logging.getLogger(__name__)

MAX_PIECE_VERTICES = 255  # PhysX cooks convex meshes of at most 255 vertices
MIN_KEPT_VERTICES = 64  # a larger hull keeps at least this many of its vertices
KEPT_VERTICES_STEP = 32  # and more, this many at a time, until within HULL_TOLERANCE
HULL_TOLERANCE = 1.5e-3  # [m] how far the reduced hull may lie inside the full one
PLANE_TOLERANCE = 1e-3  # [m] a vertex this close to the hull of the others is dropped
SLIVER_VOLUME_FRACTION = 1e-4  # of the total volume of the given pieces
NEARLY_CONVEX_RATIO = 1.02  # hull volume / mesh volume of a mesh taken as its hull
COACD_THRESHOLD = 0.05  # CoACD's concavity threshold (its default)
COACD_SEED = 0
# CoACD's search, lighter than its defaults (resolution 50, 150 iterations, depth 3):
# measured on the Kinova JACO2's link meshes (4-8k vertices), 2.2 to 2.6 times faster,
# the pieces' volume within 0.5 % of the default's (4 % on its 3.7k-vertex arm link).
COACD_SEARCH = {"preprocess_resolution": 30, "mcts_iterations": 60, "mcts_max_depth": 2}
METHOD_HULL = "hull"
METHOD_GIVEN = "given pieces"
METHOD_COACD = "coacd"
CACHE_KIND = "decompositions"
# Part of the cache key: bump it when the way pieces are made changes.
PROCEDURE_VERSION = 1


@dataclass(frozen=True)
class ConvexPieces:
    """Convex pieces of a mesh.

    pieces: each a closed convex hull of at most MAX_PIECE_VERTICES vertices, in the mesh
        file's frame [m] (after scale).
    files: one OBJ file per piece in the cache (same order).
    method: "hull", "given pieces" or "coacd".
    """

    pieces: tuple[trimesh.Trimesh, ...]
    files: tuple[Path, ...]
    method: str

    @property
    def vertices(self) -> NDArray[np.float64]:
        """(n, 3) every piece's vertices [m], stacked."""
        return np.concatenate([np.asarray(p.vertices, dtype=float) for p in self.pieces])


def check_mesh_file(path: Path | str) -> Path:
    """`path` when it names an existing file of a known mesh format; DescriptionError
    otherwise (the file is not read)."""
    return mesh_file(path, "mesh file")


def load_mesh(path: Path | str, scale: Sequence[float] = (1.0, 1.0, 1.0)) -> trimesh.Trimesh:
    """The triangles of a mesh file (graspframe.common.files.MESH_SUFFIXES: OBJ, STL, COLLADA,
    glTF, PLY; a scene graph is applied and its meshes merged), vertices times `scale`
    per axis and those at the same place merged; materials and textures are not read.
    DescriptionError for a missing file, an unknown suffix or no triangles."""
    path = check_mesh_file(path)
    try:
        loaded = trimesh.load(path, force="mesh", process=False, skip_materials=True)
    except Exception as exc:
        raise DescriptionError(f"mesh file {path} cannot be read: {exc}") from None
    mesh = loaded if isinstance(loaded, trimesh.Trimesh) else None
    if mesh is None or len(mesh.faces) == 0:
        raise DescriptionError(f"mesh file {path} has no triangles")
    vertices = np.asarray(mesh.vertices, dtype=float) * _scale(scale, path)
    # process: vertices at the same place are merged (an STL stores each triangle's own,
    # an OBJ splits them on texture seams), so connectivity and watertightness are real.
    return trimesh.Trimesh(vertices, np.asarray(mesh.faces), process=True)


def _scale(scale: Sequence[float], path: Path) -> NDArray[np.float64]:
    s = np.asarray(scale, dtype=float).reshape(-1)
    if s.shape != (3,) or not np.all(np.isfinite(s)) or not np.all(s > 0):
        raise DescriptionError(
            f"mesh file {path}: scale must be three finite numbers > 0 (x, y, z), got {scale}"
        )
    return s


def convex_hull(points: NDArray[np.float64], lazy: bool = False) -> trimesh.Trimesh | None:
    """The closed convex hull of points, with at most MAX_PIECE_VERTICES vertices (see the
    module docstring); None when the points span no volume. lazy: drop the flat vertices
    with `without_flat_vertices_lazy` (CoACD's pieces)."""
    from scipy.spatial import ConvexHull, QhullError

    points = np.asarray(points, dtype=float).reshape(-1, 3)
    try:
        corners = points[ConvexHull(points).vertices]
        if len(corners) > MIN_KEPT_VERTICES:
            corners = reduced_hull_vertices(corners)
        drop = without_flat_vertices_lazy if lazy else without_flat_vertices
        corners = drop(corners, PLANE_TOLERANCE)
        mesh = trimesh.convex.convex_hull(corners)
    except (QhullError, ValueError):
        return None
    if not (mesh.is_watertight and mesh.volume > 0):
        return None
    return mesh


def reduced_hull_vertices(corners: NDArray[np.float64]) -> NDArray[np.float64]:
    """The fewest of a hull's vertices `corners` (n, 3), in farthest-point order, whose
    hull lies within HULL_TOLERANCE inside the full hull: MIN_KEPT_VERTICES, then
    KEPT_VERTICES_STEP more at a time, at most MAX_PIECE_VERTICES. A dense scanned hull
    (thousands of vertices) keeps few; a hull of long flat faces and sharp edges, such as
    a vendor's convex link, keeps what its edges need."""
    ordered = farthest_points(corners, min(len(corners), MAX_PIECE_VERTICES))
    counts = [*range(MIN_KEPT_VERTICES, len(ordered), KEPT_VERTICES_STEP), len(ordered)]
    for count in counts:
        kept = ordered[:count]
        if inner_gap(corners, trimesh.convex.convex_hull(kept)) <= HULL_TOLERANCE:
            break
    return kept


def inner_gap(points: NDArray[np.float64], piece: trimesh.Trimesh) -> float:
    """[m] how far the points (n, 3) reach outside the convex piece at most (0 when all
    lie inside): the error of a piece that approximates their hull from inside."""
    from scipy.spatial import ConvexHull

    planes = ConvexHull(np.asarray(piece.vertices, dtype=float)).equations
    heights = np.asarray(points, dtype=float).reshape(-1, 3) @ planes[:, :3].T + planes[:, 3]
    return max(0.0, float(heights.max(axis=1).max()))


def _height_above_others(points: NDArray[np.float64], index: int) -> float:
    """[m] how far points[index] lies outside the hull of the other points (the largest
    signed distance to the planes of its faces); inf when the others span no volume."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        planes = ConvexHull(np.delete(points, index, axis=0)).equations
    except (QhullError, ValueError):
        return math.inf
    return float((planes[:, :3] @ points[index] + planes[:, 3]).max())


def without_flat_vertices(points: NDArray[np.float64], tolerance: float) -> NDArray[np.float64]:
    """The hull vertices `points` without those closer than `tolerance` [m] to the hull
    of the others, dropped one at a time, the closest first (a tetrahedron is kept)."""
    points = np.asarray(points, dtype=float)
    while len(points) > 4:
        heights = [_height_above_others(points, i) for i in range(len(points))]
        lowest = int(np.argmin(heights))
        if heights[lowest] >= tolerance:
            break
        points = np.delete(points, lowest, axis=0)
    return points


def without_flat_vertices_lazy(
    points: NDArray[np.float64], tolerance: float
) -> NDArray[np.float64]:
    """`without_flat_vertices`, with each vertex's height kept from the round it was
    measured in and measured again only when it is the lowest kept: one hull per drop
    instead of one per vertex. Dropping a vertex mostly raises the others' heights, so
    the order may differ from the exact one where it does not: every vertex dropped is
    still within `tolerance` of the hull of the others when it goes. For CoACD's pieces
    of a CAD mesh (hundreds of coplanar vertices), 58,000 hulls become about 1,000."""
    import heapq

    points = np.asarray(points, dtype=float)
    alive = list(range(len(points)))
    heap = [(_height_above_others(points, i), i) for i in alive]
    heapq.heapify(heap)
    while len(alive) > 4 and heap:
        _stale, index = heapq.heappop(heap)
        kept = points[alive]
        height = _height_above_others(kept, alive.index(index))
        if heap and (height, index) > heap[0]:
            heapq.heappush(heap, (height, index))  # measured again: not the lowest now
            continue
        if height >= tolerance:
            break
        alive.remove(index)
    return points[alive]


def farthest_points(points: NDArray[np.float64], count: int) -> NDArray[np.float64]:
    """`count` of the points, spread out: first the extreme points along the axes and the
    diagonals (up to 14), then repeatedly the point farthest from those chosen."""
    directions = np.array(
        [[1, 0, 0], [0, 1, 0], [0, 0, 1], *[[sx, sy, 1] for sx in (1, -1) for sy in (1, -1)]],
        dtype=float,
    )
    directions = np.concatenate([directions, -directions])
    chosen: list[int] = []
    for index in np.argmax(points @ directions.T, axis=0):
        if int(index) not in chosen and len(chosen) < count:
            chosen.append(int(index))
    distance = np.min(np.linalg.norm(points[:, None] - points[chosen][None], axis=2), axis=1)
    while len(chosen) < count:
        index = int(np.argmax(distance))
        chosen.append(index)
        distance = np.minimum(distance, np.linalg.norm(points - points[index], axis=1))
    return points[chosen]


def _given(path: Path, scale: Sequence[float]) -> list[trimesh.Trimesh]:
    """The convex hulls of the connected parts of `path`, slivers dropped."""
    mesh = load_mesh(path, scale)
    parts = mesh.split(only_watertight=False)
    hulls = [h for h in (convex_hull(p.vertices) for p in parts) if h is not None]
    total = sum(h.volume for h in hulls)
    kept = [h for h in hulls if h.volume >= SLIVER_VOLUME_FRACTION * total]
    if not kept:
        raise DescriptionError(f"convex pieces file {path} has no part with a volume")
    log.info("%s: %d parts, %d convex pieces kept", path.name, len(parts), len(kept))
    return kept


def _decomposed(mesh: trimesh.Trimesh, path: Path) -> tuple[list[trimesh.Trimesh], str]:
    """(pieces, method) of a mesh: its hull when it is nearly convex, else CoACD's."""
    hull = convex_hull(mesh.vertices)
    if hull is None:
        raise DescriptionError(f"mesh file {path} is flat: it spans no volume")
    solid = mesh.is_watertight and mesh.is_volume and mesh.volume > 0
    if solid and trimesh.convex.convex_hull(mesh).volume <= NEARLY_CONVEX_RATIO * mesh.volume:
        gap_mm = 1000 * inner_gap(mesh.vertices, hull)
        log.info(
            "%s: its convex hull, %d vertices, within %.2f mm",
            path.name,
            len(hull.vertices),
            gap_mm,
        )
        return [hull], METHOD_HULL
    import coacd

    log.info("%s: convex decomposition with CoACD (once; cached)", path.name)
    coacd.set_log_level("error")
    parts = coacd.run_coacd(
        coacd.Mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces)),
        threshold=COACD_THRESHOLD,
        max_ch_vertex=MAX_PIECE_VERTICES,
        seed=COACD_SEED,
        **COACD_SEARCH,
    )
    hulls = (convex_hull(np.asarray(v), lazy=True) for v, _ in parts)
    pieces = [h for h in hulls if h is not None]
    if not pieces:
        raise DescriptionError(f"mesh file {path}: the convex decomposition gave no piece")
    return pieces, METHOD_COACD


def _cache_key(source: Path, scale: Sequence[float], given: bool) -> str:
    digest = hashlib.sha256(f"convex pieces {PROCEDURE_VERSION} {ENTRY_FORMAT}".encode())
    digest.update(source.read_bytes())
    parameters = (
        [float(s) for s in scale],
        given,
        MAX_PIECE_VERTICES,
        MIN_KEPT_VERTICES,
        KEPT_VERTICES_STEP,
        HULL_TOLERANCE,
        PLANE_TOLERANCE,
        SLIVER_VOLUME_FRACTION,
        NEARLY_CONVEX_RATIO,
        COACD_THRESHOLD,
        COACD_SEED,
        sorted(COACD_SEARCH.items()),
    )
    digest.update(repr(parameters).encode())
    return digest.hexdigest()


def decompositions_dir() -> Path:
    """The cache folder of convex pieces."""
    return cache_dir(CACHE_KIND)


def _pieces_of(entry: CacheEntry) -> ConvexPieces:
    """The pieces of a whole cache entry (graspframe/common/cache.py checked its files)."""
    files = tuple(entry.files.values())
    pieces = []
    for path in files:
        piece = trimesh.load(path, force="mesh", process=False)
        assert isinstance(piece, trimesh.Trimesh)  # force="mesh" loads one mesh
        pieces.append(piece)
    return ConvexPieces(tuple(pieces), files, str(entry.values["method"]))


def convex_pieces(
    mesh_path: Path | str,
    scale: Sequence[float] = (1.0, 1.0, 1.0),
    given_pieces: Path | str | None = None,
) -> ConvexPieces:
    """The convex pieces of a mesh file, from the cache when it holds them (see the module
    docstring for the rules). mesh_path: the mesh; scale: per axis, applied to the file's
    vertices (e.g. 0.001 for millimetres); given_pieces: a file of convex parts to use
    instead of decomposing the mesh. DescriptionError for a file that cannot be used."""
    check_mesh_file(mesh_path)
    if given_pieces is not None:
        check_mesh_file(given_pieces)
    source = Path(given_pieces) if given_pieces is not None else Path(mesh_path)
    _scale(scale, source)
    folder = decompositions_dir() / _cache_key(source, scale, given_pieces is not None)
    entry = read_entry(folder)
    if entry is None:
        if given_pieces is not None:
            pieces, method = _given(source, scale), METHOD_GIVEN
        else:
            pieces, method = _decomposed(load_mesh(source, scale), source)
        files = {
            f"piece_{index:03d}.obj": trimesh.exchange.obj.export_obj(
                piece, include_normals=False
            ).encode()
            for index, piece in enumerate(pieces)
        }
        # Every caller reads the pieces back from the files, so all see the same numbers.
        entry = write_entry(folder, {"method": method}, files)
    return _pieces_of(entry)
