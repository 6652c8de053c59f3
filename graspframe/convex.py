"""Convex pieces of a mesh file, computed once and cached.

The physics (PhysX takes every collision mesh as a convex hull of at most 255 vertices),
the collision checker (coal `Convex`) and the pictures must see the same solid, so a
mesh that takes part in collisions is replaced everywhere by convex pieces computed
here: its convex hull, simplified to at most `MAX_PIECE_VERTICES` vertices (a hull with
more would be simplified differently by PhysX).

Entries live under `<cache>/decompositions/<key>/` (key: a hash of the file's bytes and
the parameters): one OBJ file per piece, then `manifest.json`, written last; an entry
without a manifest is not trusted and is computed again.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import ArrayLike

from graspframe.errors import DescriptionError
from graspframe.files import atomic_write, cache_dir

MAX_PIECE_VERTICES = 64
MESH_SUFFIXES = (".obj", ".stl", ".dae", ".glb", ".gltf", ".ply")
_VERSION = 1  # raise when the pieces computed for the same input change


@dataclass(frozen=True)
class ConvexPieces:
    """pieces: convex meshes in the mesh file's frame [m] (scale applied), each with at
    most MAX_PIECE_VERTICES vertices; files: one OBJ file per piece in the cache (for
    loaders that read files); method: how they were made ("hull")."""

    pieces: tuple[trimesh.Trimesh, ...]
    files: tuple[Path, ...]
    method: str


def load_mesh(path: Path) -> trimesh.Trimesh:
    """One triangle mesh from a mesh file (every part of a scene merged) [file units];
    DescriptionError for a missing file, an unknown format or an empty mesh."""
    path = Path(path)
    if not path.is_file():
        raise DescriptionError(f"mesh file not found: {path}")
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise DescriptionError(
            f"mesh {path.name}: unknown format {path.suffix!r}; formats: {', '.join(MESH_SUFFIXES)}"
        )
    try:
        mesh = trimesh.load_mesh(path, process=False)
    except Exception as exc:
        raise DescriptionError(f"cannot read mesh {path}: {exc}") from exc
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise DescriptionError(f"mesh {path} has no triangles")
    return mesh


def simplified_hull(points: ArrayLike, max_vertices: int = MAX_PIECE_VERTICES) -> trimesh.Trimesh:
    """The convex hull of `points` with at most `max_vertices` vertices: when it has
    more, the hull of a farthest-point subset of its vertices (extreme points first)."""
    hull = trimesh.convex.convex_hull(np.asarray(points, dtype=float))
    vertices = np.asarray(hull.vertices)
    if len(vertices) <= max_vertices:
        return hull
    chosen = [int(np.argmax(np.linalg.norm(vertices - vertices.mean(axis=0), axis=1)))]
    distance = np.linalg.norm(vertices - vertices[chosen[0]], axis=1)
    while len(chosen) < max_vertices:
        index = int(np.argmax(distance))
        chosen.append(index)
        distance = np.minimum(distance, np.linalg.norm(vertices - vertices[index], axis=1))
    return trimesh.convex.convex_hull(vertices[chosen])


def _key(path: Path, scale: tuple[float, float, float]) -> str:
    digest = hashlib.sha256(Path(path).read_bytes())
    digest.update(repr((_VERSION, MAX_PIECE_VERTICES, path.suffix.lower(), scale)).encode())
    return digest.hexdigest()[:24]


def _read_entry(folder: Path) -> ConvexPieces | None:
    manifest = folder / "manifest.json"
    try:
        entry = json.loads(manifest.read_text())
        files = tuple(folder / name for name in entry["files"])
        pieces = tuple(trimesh.load_mesh(f, process=False) for f in files)
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not pieces or any(len(p.vertices) < 4 for p in pieces):
        return None
    return ConvexPieces(pieces, files, entry["method"])


def convex_pieces(mesh_path: Path | str, scale: ArrayLike = (1.0, 1.0, 1.0)) -> ConvexPieces:
    """The convex pieces of a mesh file after `scale` (per axis), from the cache or
    computed and cached."""
    mesh_path = Path(mesh_path)
    sx, sy, sz = (float(s) for s in np.broadcast_to(np.asarray(scale, dtype=float), (3,)))
    scale3 = (sx, sy, sz)
    mesh = load_mesh(mesh_path)
    folder = cache_dir("decompositions") / _key(mesh_path, scale3)
    cached = _read_entry(folder)
    if cached is not None:
        return cached
    hull = simplified_hull(np.asarray(mesh.vertices) * np.asarray(scale3))
    folder.mkdir(parents=True, exist_ok=True)
    names = ["piece_000.obj"]
    atomic_write(folder / names[0], trimesh.exchange.obj.export_obj(hull))
    atomic_write(folder / "manifest.json", json.dumps({"files": names, "method": "hull"}))
    return ConvexPieces((hull,), tuple(folder / n for n in names), "hull")
